// Run by ctest as `mpirun -np 2 test_mpi` (tests/CMakeLists.txt): every rank runs every test case
// in the same order, so the collectives meet.
#include <catch2/catch.hpp>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/mpi/mpi_communicator.hpp"

namespace {

rdsim::Communicator& comm() {
  static std::unique_ptr<rdsim::Communicator> c = rdsim::make_mpi_communicator();
  return *c;
}

}  // namespace

TEST_CASE("mpi: two ranks", "[mpi]") {
  REQUIRE(comm().size() == 2);
  CHECK(comm().local_size() == 2);
  CHECK((comm().rank() == 0 || comm().rank() == 1));
  CHECK(comm().name() == "mpi");
}

TEST_CASE("mpi: allreduce_sum gives every rank the same sums", "[mpi]") {
  const int r = comm().rank();
  std::vector<float> f(1000);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = static_cast<float>(i) + 0.5f * static_cast<float>(r);
  const long long bytes_before = comm().allreduce_traffic().bytes;
  comm().allreduce_sum(f.data(), f.size());
  for (std::size_t i = 0; i < f.size(); ++i) CHECK(f[i] == 2.0f * static_cast<float>(i) + 0.5f);
  CHECK(comm().allreduce_traffic().bytes - bytes_before == 4000);
  double d = r + 0.5;
  comm().allreduce_sum(&d, 1);
  CHECK(d == 2.0);
}

TEST_CASE("mpi: allgather, broadcast and gather", "[mpi]") {
  const int r = comm().rank();
  const double mine[2] = {10.0 * r, 10.0 * r + 1};
  std::vector<double> all(4);
  comm().allgather(mine, 2, all.data());
  CHECK(all == std::vector<double>{0, 1, 10, 11});

  const std::uint64_t hash = 0xABCDull + static_cast<std::uint64_t>(r);
  std::vector<std::uint64_t> hashes(2);
  comm().allgather(&hash, 1, hashes.data());
  CHECK(hashes == std::vector<std::uint64_t>{0xABCD, 0xABCE});

  std::string bytes = r == 0 ? std::string(100000, 'w') : "stale";
  comm().broadcast(bytes, 0);
  CHECK(bytes == std::string(100000, 'w'));
  std::string empty = r == 1 ? "" : "x";
  comm().broadcast(empty, 1);
  CHECK(empty.empty());

  const std::vector<std::string> parts = comm().gather("rank " + std::to_string(r) + std::string(static_cast<std::size_t>(r) * 5, '!'), 0);
  if (r == 0)
    CHECK(parts == std::vector<std::string>{"rank 0", "rank 1!!!!!"});
  else
    CHECK(parts.empty());
}
