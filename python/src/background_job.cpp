#include "background_job.hpp"

#include <new>

namespace rdsim::python {

BackgroundJob::~BackgroundJob() {
  if (thread_.joinable() && !owner_.here()) {  // a fork: the thread is not in this process
    new std::thread(std::move(thread_));        // leaked on purpose: never joined
    // Fresh synchronisation objects: the copies still count the parent's waiting thread (see
    // WorkerPool's destructor).
    new (&mutex_) std::mutex();
    new (&wake_) std::condition_variable();
    new (&done_) std::condition_variable();
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void BackgroundJob::start(std::function<void()> job) {
  owner_.require("a vector env's step_async helper thread");
  if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(job);
    error_ = nullptr;
    has_job_ = true;
  }
  busy_ = true;
  wake_.notify_one();
}

void BackgroundJob::wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return !has_job_; });
  busy_ = false;
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void BackgroundJob::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return has_job_ || quit_; });
    if (quit_) return;
    lock.unlock();
    std::exception_ptr error;
    try {
      job_();
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    error_ = error;
    has_job_ = false;
    done_.notify_all();
  }
}

}  // namespace rdsim::python
