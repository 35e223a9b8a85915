#include "rdsim/parallel/communicator.hpp"

#include <chrono>
#include <cstdlib>
#include <cstring>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

class SingleProcess final : public Communicator {
public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  int local_size() const override { return 1; }
  std::string name() const override { return "single process"; }
  [[noreturn]] void abort(int exit_code) override { std::exit(exit_code); }

protected:
  void do_allreduce_sum(float*, std::size_t) override {}
  void do_allreduce_sum(double*, std::size_t) override {}
  void do_allgather(const void* send, std::size_t bytes_each, void* recv) override {
    if (bytes_each > 0) std::memcpy(recv, send, bytes_each);
  }
  void do_broadcast(std::string&, int) override {}
  std::vector<std::string> do_gather(const std::string& bytes, int) override { return {bytes}; }
};

std::optional<int> env_int(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return std::nullopt;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  if (*end != '\0' || n < 0 || n > 1'000'000) return std::nullopt;
  return static_cast<int>(n);
}

}  // namespace

template <class Reduce>
void Communicator::count(std::size_t bytes, Reduce reduce) {
  const auto t0 = std::chrono::steady_clock::now();
  reduce();
  traffic_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  traffic_.calls += 1;
  traffic_.bytes += static_cast<long long>(bytes);
}

void Communicator::allreduce_sum(float* data, std::size_t n) {
  if (size() == 1) return;
  count(n * sizeof(float), [&] { do_allreduce_sum(data, n); });
}

void Communicator::allreduce_sum(double* data, std::size_t n) {
  if (size() == 1) return;
  count(n * sizeof(double), [&] { do_allreduce_sum(data, n); });
}

void Communicator::allgather(const double* send, std::size_t n, double* recv) {
  do_allgather(send, n * sizeof(double), recv);
}

void Communicator::allgather(const std::uint64_t* send, std::size_t n, std::uint64_t* recv) {
  do_allgather(send, n * sizeof(std::uint64_t), recv);
}

void Communicator::broadcast(std::string& bytes, int root) {
  if (root < 0 || root >= size()) throw Error("broadcast: no rank " + std::to_string(root));
  do_broadcast(bytes, root);
}

std::vector<std::string> Communicator::gather(const std::string& bytes, int root) {
  if (root < 0 || root >= size()) throw Error("gather: no rank " + std::to_string(root));
  return do_gather(bytes, root);
}

Communicator& single_process_communicator() {
  static SingleProcess comm;
  return comm;
}

std::unique_ptr<Communicator> make_single_process_communicator() { return std::make_unique<SingleProcess>(); }

std::optional<int> launcher_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (auto n = env_int(name)) return n;
  return std::nullopt;
}

int launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (auto n = env_int(name)) return *n;
  return 0;
}

}  // namespace rdsim
