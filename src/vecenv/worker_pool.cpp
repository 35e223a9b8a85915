#include "rdsim/vecenv/worker_pool.hpp"

#include <chrono>
#include <new>
#include <sched.h>

#include "rdsim/core/error.hpp"

namespace rdsim {

WorkerPool::WorkerPool(int threads) {
  if (threads < 1) throw Error("WorkerPool: at least one thread expected, got " + std::to_string(threads));
  errors_.resize(static_cast<std::size_t>(threads));
  threads_.reserve(static_cast<std::size_t>(threads - 1));
  for (int w = 1; w < threads; ++w) threads_.emplace_back([this, w] { worker_main(w); });
}

WorkerPool::~WorkerPool() {
  if (threads_.empty()) return;
  if (!owner_.here()) {
    // A fork: the threads are not in this process, so nothing is joined, and the copies of the
    // mutex and condition variables, which still count the parent's waiting workers (glibc's
    // pthread_cond_destroy would wait for them forever), are replaced by fresh ones before the
    // members' destructors run (reusing their storage ends the copies' lifetime).
    new std::vector<std::thread>(std::move(threads_));  // leaked on purpose: no thread to end
    new (&mutex_) std::mutex();
    new (&job_ready_) std::condition_variable();
    new (&job_done_) std::condition_variable();
    return;
  }
  stop_.store(true);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    start_.generation.fetch_add(1);
  }
  job_ready_.notify_all();
  for (auto& t : threads_) t.join();
}

void WorkerPool::run_erased(void (*call)(void*, int), void* job) {
  if (threads_.empty()) {  // the calling thread alone: works in a fork too
    call(job, 0);
    return;
  }
  start_erased(call, job);
  try {
    call(job, 0);
  } catch (...) {
    errors_[0] = std::current_exception();
  }
  join();
}

void WorkerPool::start_erased(void (*call)(void*, int), void* job) {
  owner_.require("a vector env's worker pool");
  if (threads_.empty()) return;
  start_.call = call;
  start_.job = job;
  pending_.store(static_cast<int>(threads_.size()));
  // seq_cst store then load; a worker stores sleepers_ then loads start_.generation: one of the two
  // sides sees the other's write, so a worker that went to sleep is always woken.
  start_.generation.fetch_add(1);
  if (sleepers_.load() > 0) {
    { std::lock_guard<std::mutex> lock(mutex_); }
    job_ready_.notify_all();
  }
}

void WorkerPool::join() {
  if (threads_.empty()) return;
  if (!spin_until([this] { return pending_.load(std::memory_order_acquire) == 0; })) {
    std::unique_lock<std::mutex> lock(mutex_);
    caller_sleeping_.store(true);
    job_done_.wait(lock, [this] { return pending_.load() == 0; });
    caller_sleeping_.store(false);
  }
  for (auto& e : errors_) {
    if (e) {
      std::exception_ptr first = e;
      for (auto& x : errors_) x = nullptr;
      std::rethrow_exception(first);
    }
  }
}

void WorkerPool::worker_main(int w) {
  std::uint64_t seen = 0;
  for (;;) {
    if (!spin_until([&] { return start_.generation.load(std::memory_order_acquire) != seen; })) {
      std::unique_lock<std::mutex> lock(mutex_);
      sleepers_.fetch_add(1);
      job_ready_.wait(lock, [&] { return start_.generation.load() != seen; });
      sleepers_.fetch_sub(1);
    }
    seen = start_.generation.load(std::memory_order_acquire);
    if (stop_.load()) return;
    try {
      start_.call(start_.job, w);
    } catch (...) {
      errors_[static_cast<std::size_t>(w)] = std::current_exception();
    }
    if (pending_.fetch_sub(1) == 1 && caller_sleeping_.load()) {
      { std::lock_guard<std::mutex> lock(mutex_); }
      job_done_.notify_one();
    }
  }
}

int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    const int n = CPU_COUNT(&set);
    if (n > 0) return n;
  }
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

}  // namespace rdsim
