#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/vecenv/worker_pool.hpp"

using rdsim::WorkerPool;

TEST_CASE("WorkerPool runs every worker once per job, worker 0 on the caller", "[pool]") {
  for (int threads : {1, 2, 3, 8}) {
    WorkerPool pool(threads);
    REQUIRE(pool.size() == threads);
    std::vector<std::thread::id> first(static_cast<std::size_t>(threads));
    std::vector<int> calls(static_cast<std::size_t>(threads), 0);
    pool.run([&](int w) {
      first[static_cast<std::size_t>(w)] = std::this_thread::get_id();
      ++calls[static_cast<std::size_t>(w)];
    });
    CHECK(first[0] == std::this_thread::get_id());
    for (int w = 1; w < threads; ++w) CHECK(first[static_cast<std::size_t>(w)] != first[0]);
    // Back-to-back jobs (one per env step): each worker stays the same thread.
    bool same_threads = true;
    for (int job = 0; job < 2000; ++job) {
      pool.run([&](int w) {
        same_threads = same_threads && (std::this_thread::get_id() == first[static_cast<std::size_t>(w)]);
        ++calls[static_cast<std::size_t>(w)];
      });
    }
    CHECK(same_threads);
    for (int c : calls) CHECK(c == 2001);
  }
}

TEST_CASE("WorkerPool: a job sees the caller's writes and the caller sees the job's", "[pool]") {
  WorkerPool pool(4);
  std::vector<long long> data(4, 0);
  for (int job = 1; job <= 500; ++job) {
    for (auto& d : data) d += job;  // caller writes before the job
    pool.run([&](int w) { data[static_cast<std::size_t>(w)] *= 2; });
    for (auto& d : data) d /= 2;  // ... and reads after it
  }
  for (long long d : data) CHECK(d == 500LL * 501 / 2);
}

TEST_CASE("WorkerPool: a job that throws is rethrown in the caller after every worker finished", "[pool]") {
  WorkerPool pool(3);
  std::atomic<int> finished{0};
  auto job = [&](int w) {
    if (w >= 1) throw rdsim::Error("worker " + std::to_string(w));
    finished.fetch_add(1);
  };
  CHECK_THROWS_WITH(pool.run(job), "worker 1");  // the lowest failing worker
  CHECK(finished.load() == 1);
  // The pool keeps working afterwards.
  std::atomic<int> calls{0};
  pool.run([&](int) { calls.fetch_add(1); });
  CHECK(calls.load() == 3);
  CHECK_THROWS_AS(WorkerPool(0), rdsim::Error);
}

TEST_CASE("WorkerPool: workers that went to sleep wake for the next job", "[pool]") {
  WorkerPool pool(2);
  std::atomic<int> calls{0};
  for (int job = 0; job < 3; ++job) {
    // Longer than the spin: the worker sleeps on its condition variable in between.
    std::this_thread::sleep_for(std::chrono::microseconds(5 * WorkerPool::kSpinMicros));
    pool.run([&](int w) {
      if (w == 1) std::this_thread::sleep_for(std::chrono::microseconds(3 * WorkerPool::kSpinMicros));
      calls.fetch_add(1);
    });
  }
  CHECK(calls.load() == 6);
}

TEST_CASE("WorkerPool: start() runs the workers' share while the caller goes on, join() waits", "[pool]") {
  WorkerPool pool(3);
  std::atomic<int> release{0};
  std::vector<int> ran(3, 0);
  auto job = [&](int w) {
    while (release.load() == 0) {}  // held until the caller, still free, lets go
    ran[static_cast<std::size_t>(w)] = 1;
  };
  pool.start(job);
  release.store(1);  // reached: start() returned while the workers were busy
  pool.join();
  CHECK(ran == std::vector<int>{0, 1, 1});  // worker 0 is the caller, which did not run the job
  auto failing = [](int w) {
    if (w == 2) throw std::runtime_error("worker 2");
  };
  pool.start(failing);
  CHECK_THROWS_WITH(pool.join(), "worker 2");
  pool.run([&](int w) { ran[static_cast<std::size_t>(w)] = 2; });  // the pool works on
  CHECK(ran == std::vector<int>{2, 2, 2});
}

TEST_CASE("available_cores counts the cores this process may use", "[pool]") {
  const int n = rdsim::available_cores();
  CHECK(n >= 1);
  CHECK(n <= static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
}

// fork() copies a pool but not its threads: in the forked process a job is one clear error (never a
// wait for threads that are not there), and destroying the copy leaves the parent's threads alone.
TEST_CASE("WorkerPool in a forked process: a job is an error at once, destroying it does not wait", "[pool][fork]") {
  auto pool = std::make_unique<WorkerPool>(3);
  pool->run([](int) {});
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    int code = 1;
    try {
      pool->run([](int) {});
    } catch (const rdsim::Error& e) {
      code = std::string(e.what()).find("a fork of it") != std::string::npos ? 0 : 2;
    }
    pool.reset();  // must return: no join of the parent's threads
    _exit(code);
  }
  int status = 0;
  pid_t done = 0;
  for (int waited_ms = 0; waited_ms < 20'000 && (done = waitpid(child, &status, WNOHANG)) == 0; waited_ms += 10)
    usleep(10'000);
  if (done == 0) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    FAIL("the forked process hung");
  }
  REQUIRE(done == child);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  int calls = 0;
  pool->run([&](int w) {
    if (w == 0) ++calls;
  });
  CHECK(calls == 1);  // the parent's pool still works
}
