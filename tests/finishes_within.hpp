#pragma once
// Runs a call that must not block (opening a FIFO, reading a device) on its own thread and says
// whether it returned within the time limit. A call that blocks is left behind on its detached
// thread (it cannot be cancelled) and the test fails instead of hanging until ctest's timeout.
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <thread>

namespace rdsim::test {

struct Finished {
  bool in_time = false;
  bool threw = false;
  std::string message;  // what() of what it threw
};

inline Finished finishes_within(std::chrono::milliseconds limit, std::function<void()> call) {
  auto done = std::make_shared<std::promise<Finished>>();
  std::future<Finished> result = done->get_future();
  std::thread([done, call = std::move(call)] {
    Finished f;
    f.in_time = true;
    try {
      call();
    } catch (const std::exception& e) {
      f.threw = true;
      f.message = e.what();
    }
    done->set_value(f);
  }).detach();
  if (result.wait_for(limit) != std::future_status::ready) return Finished{};
  return result.get();
}

}  // namespace rdsim::test
