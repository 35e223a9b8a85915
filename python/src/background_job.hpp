#pragma once
// One helper thread that runs one job at a time: what lets VecEnv steps run while Python works
// (rdsim's make_vec step_async / step_wait). The thread starts with the first job and lives until
// the object is destroyed.
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

#include "rdsim/core/process_owner.hpp"

namespace rdsim::python {

class BackgroundJob {
public:
  BackgroundJob() = default;
  ~BackgroundJob();
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;

  // Starts `job` on the helper thread; the previous job must have been waited for.
  void start(std::function<void()> job);
  // Waits for the job started last and rethrows its exception, if any.
  void wait();
  bool busy() const { return busy_; }

private:
  void run();

  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void()> job_;
  std::exception_ptr error_;
  bool has_job_ = false, quit_ = false, busy_ = false;
  ProcessOwner owner_;  // a forked copy neither starts jobs nor joins the parent's thread
};

}  // namespace rdsim::python
