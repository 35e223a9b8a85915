#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "rdsim/training/checkpoint.hpp"

using namespace std::chrono_literals;

TEST_CASE("checkpoints are due every checkpoint_interval env steps, counted from the start", "[checkpoint]") {
  rdsim::CheckpointSchedule s(1000, 0.0, 0);
  CHECK_FALSE(s.due(999));
  CHECK(s.due(1000));
  s.start();
  s.done(1024);  // saved a little past the boundary: the next one is still at 2000
  CHECK_FALSE(s.due(1999));
  CHECK(s.due(2000));
  // A run resumed at 2500 steps keeps the same boundaries.
  rdsim::CheckpointSchedule resumed(1000, 0.0, 2500);
  CHECK_FALSE(resumed.due(2999));
  CHECK(resumed.due(3000));
  // Both off: never due.
  rdsim::CheckpointSchedule off(0, 0.0, 0);
  CHECK_FALSE(off.due(1'000'000'000));
}

TEST_CASE("checkpoints are due every checkpoint_seconds, stretched to 20 times a slow write", "[checkpoint]") {
  rdsim::CheckpointSchedule hourly(0, 3600.0, 0);
  CHECK_FALSE(hourly.due(1));
  rdsim::CheckpointSchedule fast(0, 0.001, 0);
  std::this_thread::sleep_for(5ms);
  CHECK(fast.due(1));
  // A write that took 0.1 s moves the next one at least 2 s away, however short the period.
  fast.start();
  std::this_thread::sleep_for(100ms);
  fast.done(2);
  CHECK_FALSE(fast.due(3));
}
