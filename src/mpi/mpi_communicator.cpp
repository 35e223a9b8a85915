#include "rdsim/mpi/mpi_communicator.hpp"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdint>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

// MPI counts are ints: larger buffers go in slices.
constexpr std::size_t kSlice = static_cast<std::size_t>(INT_MAX) / 8;

void check(int status, const char* what) {
  if (status == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(status, text, &length);
  throw Error(std::string("mpi: ") + what + " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

class MpiCommunicator final : public Communicator {
public:
  MpiCommunicator() {
    int provided = 0;
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    // Errors come back as codes (turned into rdsim::Error) instead of aborting inside MPI.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm local;
    check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &local),
          "MPI_Comm_split_type");
    MPI_Comm_size(local, &local_size_);
    MPI_Comm_free(&local);
  }
  ~MpiCommunicator() override { MPI_Finalize(); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int local_size() const override { return local_size_; }
  std::string name() const override { return "mpi"; }
  [[noreturn]] void abort(int exit_code) override {
    MPI_Abort(MPI_COMM_WORLD, exit_code);
    std::exit(exit_code);  // not reached
  }

protected:
  void do_allreduce_sum(float* data, std::size_t n) override { allreduce(data, n, MPI_FLOAT); }
  void do_allreduce_sum(double* data, std::size_t n) override { allreduce(data, n, MPI_DOUBLE); }

  void do_allgather(const void* send, std::size_t bytes_each, void* recv) override {
    if (bytes_each > kSlice) throw Error("mpi: allgather of more than " + std::to_string(kSlice) + " bytes per rank");
    const int count = static_cast<int>(bytes_each);
    check(MPI_Allgather(send, count, MPI_BYTE, recv, count, MPI_BYTE, MPI_COMM_WORLD), "MPI_Allgather");
  }

  void do_broadcast(std::string& bytes, int root) override {
    std::uint64_t n = bytes.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, root, MPI_COMM_WORLD), "MPI_Bcast");
    bytes.resize(static_cast<std::size_t>(n));
    for (std::size_t at = 0; at < n; at += kSlice) {
      const int count = static_cast<int>(std::min<std::size_t>(kSlice, n - at));
      check(MPI_Bcast(bytes.data() + at, count, MPI_BYTE, root, MPI_COMM_WORLD), "MPI_Bcast");
    }
  }

  std::vector<std::string> do_gather(const std::string& bytes, int root) override {
    if (bytes.size() > kSlice) throw Error("mpi: gather of more than " + std::to_string(kSlice) + " bytes per rank");
    const int mine = static_cast<int>(bytes.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
    check(MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, root, MPI_COMM_WORLD), "MPI_Gather");
    std::string all;
    if (rank_ == root) {
      long long total = 0;
      for (int r = 0; r < size_; ++r) {
        offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
        total += counts[static_cast<std::size_t>(r)];
      }
      if (total > static_cast<long long>(INT_MAX)) throw Error("mpi: gather of more than 2 GiB in all");
      all.resize(static_cast<std::size_t>(total));
    }
    check(MPI_Gatherv(bytes.data(), mine, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, root,
                      MPI_COMM_WORLD),
          "MPI_Gatherv");
    std::vector<std::string> parts;
    if (rank_ != root) return parts;
    for (int r = 0; r < size_; ++r)
      parts.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                                 static_cast<std::size_t>(counts[static_cast<std::size_t>(r)])));
    return parts;
  }

private:
  template <class T>
  void allreduce(T* data, std::size_t n, MPI_Datatype type) {
    for (std::size_t at = 0; at < n; at += kSlice) {
      const int count = static_cast<int>(std::min(kSlice, n - at));
      check(MPI_Allreduce(MPI_IN_PLACE, data + at, count, type, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
    }
  }

  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace

std::unique_ptr<Communicator> make_mpi_communicator() { return std::make_unique<MpiCommunicator>(); }

}  // namespace rdsim
