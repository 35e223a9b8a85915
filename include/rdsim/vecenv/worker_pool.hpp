#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "rdsim/core/process_owner.hpp"

// A persistent pool of threads that run one job at a time, every worker its own share of it:
// what steps VecEnv's envs on several cores. Threads are started once, with the pool, never per
// job; worker w is always the same thread, so work given to worker w by a fixed rule (env i ->
// worker i * size / envs) always runs on the same thread and its data stays in that core's cache
// (and a renderer's context stays bound to one thread).
//
//   WorkerPool pool(4);                     // the caller + 3 threads
//   pool.run([&](int worker) { ... });      // returns when all 4 shares are done
//
// A job waits for workers that spin briefly (kSpinMicros) before they sleep, so back-to-back jobs
// (one per env step) cost a cache-line hand-off, not a system call.
namespace rdsim {

class WorkerPool {
public:
  // `threads` >= 1 workers: worker 0 is the thread that calls run(), workers 1..threads-1 are
  // threads started here and joined by the destructor.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return static_cast<int>(threads_.size()) + 1; }

  // Calls job(w) for every worker w in 0..size()-1 (w == 0 on the calling thread) and returns
  // when all have returned. With one worker it is a plain call. When workers throw, the first
  // exception (lowest worker index) is rethrown here after every worker has finished.
  // Not reentrant: one run() at a time, from one thread.
  template <class Job>
  void run(Job&& job) {
    run_erased([](void* j, int w) { (*static_cast<std::remove_reference_t<Job>*>(j))(w); }, &job);
  }

  // Starts job(w) on workers 1..size()-1 only and returns at once: the caller goes on with its
  // own work (VecEnv's pipelined groups: the workers step envs while the caller acts). join()
  // waits for them and rethrows the first exception; nothing else may run on the pool between.
  // With one worker, start() does nothing.
  template <class Job>
  void start(Job& job) {
    start_erased([](void* j, int w) { (*static_cast<Job*>(j))(w); }, &job);
  }
  void join();

  // How long a worker (and run() waiting for them) polls before it sleeps, in microseconds.
  static constexpr int kSpinMicros = 50;

private:
  void run_erased(void (*call)(void*, int), void* job);
  void start_erased(void (*call)(void*, int), void* job);
  void worker_main(int w);

  std::vector<std::thread> threads_;
  std::vector<std::exception_ptr> errors_;  // one slot per worker
  ProcessOwner owner_;  // a forked copy neither runs jobs nor joins the parent's threads

  // What the caller writes to start a job, on a cache line of its own that the workers poll; the
  // count the workers write when done on another, that the caller polls: one line crosses from
  // core to core each way per job, and neither side's polling slows the other's writes.
  struct alignas(64) Job {
    void (*call)(void*, int) = nullptr;
    void* job = nullptr;
    std::atomic<std::uint64_t> generation{0};  // bumped once per job, after call and job
  } start_;
  alignas(64) std::atomic<int> pending_{0};    // workers (threads) still busy with the job
  alignas(64) std::atomic<int> sleepers_{0};   // workers blocked on job_ready_
  std::atomic<bool> caller_sleeping_{false};
  std::atomic<bool> stop_{false};             // set before the destructor's generation bump
  std::mutex mutex_;
  std::condition_variable job_ready_, job_done_;
};

// One pause of a spin-wait: tells the core this thread is polling (x86 `pause`, ARM `yield`), so a
// sibling hardware thread and the line being polled are not starved.
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// Polls `done()` for up to WorkerPool::kSpinMicros, pausing between polls; true when it became true
// in that time (the caller then sleeps until it does).
template <class Done>
bool spin_until(Done done) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::microseconds(WorkerPool::kSpinMicros);
  for (int i = 1;; ++i) {
    if (done()) return true;
    cpu_relax();
    if (i % 64 == 0 && Clock::now() > deadline) return done();
  }
}

// Cores this process may run on: its CPU affinity mask (what mpirun's binding or taskset
// leaves it), or std::thread::hardware_concurrency() where that is unknown. At least 1.
int available_cores();

}  // namespace rdsim
