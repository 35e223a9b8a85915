#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>
#include <vector>

#include "rdsim/parallel/communicator.hpp"

TEST_CASE("the single-process communicator is rank 0 of 1 and its collectives change nothing", "[communicator]") {
  rdsim::Communicator& c = rdsim::single_process_communicator();
  CHECK(c.rank() == 0);
  CHECK(c.size() == 1);
  CHECK(c.local_size() == 1);
  std::vector<float> f = {1.5f, -2.0f};
  c.allreduce_sum(f.data(), f.size());
  CHECK(f == std::vector<float>{1.5f, -2.0f});
  double d = 3.0;
  c.allreduce_sum(&d, 1);
  CHECK(d == 3.0);
  const std::vector<double> mine = {4.0, 5.0};
  std::vector<double> all(2);
  c.allgather(mine.data(), mine.size(), all.data());
  CHECK(all == mine);
  std::string bytes = "weights";
  c.broadcast(bytes, 0);
  CHECK(bytes == "weights");
  CHECK(c.gather("abc", 0) == std::vector<std::string>{"abc"});
  CHECK(c.allreduce_traffic().calls == 0);  // one process exchanges nothing
  CHECK_THROWS(c.broadcast(bytes, 1));
}

TEST_CASE("launcher_world_size reads the MPI launcher's environment", "[communicator]") {
  const char* saved = std::getenv("OMPI_COMM_WORLD_SIZE");
  const std::string keep = saved ? saved : "";
  ::setenv("OMPI_COMM_WORLD_SIZE", "4", 1);
  CHECK(rdsim::launcher_world_size() == 4);
  ::setenv("OMPI_COMM_WORLD_SIZE", "four", 1);
  CHECK(rdsim::launcher_world_size() != 4);
  if (saved)
    ::setenv("OMPI_COMM_WORLD_SIZE", keep.c_str(), 1);
  else
    ::unsetenv("OMPI_COMM_WORLD_SIZE");
}
