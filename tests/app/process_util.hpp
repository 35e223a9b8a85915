#pragma once
// Running the real rdsim binary as a child process the test controls: argument lists without a
// shell, an address-space limit (setrlimit RLIMIT_AS, what `ulimit -v` sets), a time limit, and
// signals (SIGINT, SIGTERM, SIGKILL) at chosen moments.
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include "rl_test_util.hpp"

namespace proctest {

// AddressSanitizer reserves terabytes of shadow address space at start, so an ASan binary cannot
// run under an address-space limit at all: there the limit is left out (the Release suite checks
// the bound; the sanitizer suite checks memory errors).
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

// Splits a command line on spaces; '' is an empty argument, 'a b' one argument.
inline std::vector<std::string> split_args(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false, have = false;
  for (char c : line) {
    if (c == '\'') {
      quoted = !quoted;
      have = true;
    } else if (c == ' ' && !quoted) {
      if (have) out.push_back(cur);
      cur.clear();
      have = false;
    } else {
      cur += c;
      have = true;
    }
  }
  if (have) out.push_back(cur);
  return out;
}

struct Child {
  pid_t pid = -1;
  std::string out_path, err_path;
  bool reaped = false;
  int status = 0;
};

// Collects the child's status if it has ended; true while it runs.
inline bool running(Child& c) {
  if (c.reaped) return false;
  if (::waitpid(c.pid, &c.status, WNOHANG) == c.pid) c.reaped = true;
  return !c.reaped;
}

// Starts `RDSIM_BINARY args...` with stdout/stderr in files; `address_space` bytes at most (0: no
// limit; ignored under AddressSanitizer, see kAddressSanitizer).
inline Child start(const std::vector<std::string>& args, const std::string& out_path, const std::string& err_path,
                   unsigned long long address_space = 0) {
  Child c{-1, out_path, err_path, false, 0};
  c.pid = ::fork();
  if (c.pid == 0) {
    if (address_space > 0 && !kAddressSanitizer) {
      rlimit limit{address_space, address_space};
      ::setrlimit(RLIMIT_AS, &limit);
    }
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<char*> argv;
    std::string binary = RDSIM_BINARY;
    argv.push_back(binary.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  return c;
}

struct Outcome {
  bool exited = false;     // ended by exit()
  int exit_code = -1;
  int signal = 0;          // ended by this signal
  bool timed_out = false;  // killed by us after the time limit
  std::string out, err;
};

// Waits for the child, killing it after `timeout` (long: a shared machine or a sanitizer build is slow).
inline Outcome wait(Child& c, std::chrono::milliseconds timeout = std::chrono::minutes(10)) {
  Outcome o;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (running(c)) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(c.pid, SIGKILL);
      ::waitpid(c.pid, &c.status, 0);
      c.reaped = true;
      o.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const int status = c.status;
  o.exited = WIFEXITED(status);
  o.exit_code = o.exited ? WEXITSTATUS(status) : -1;
  o.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  o.out = rltest::slurp(c.out_path);
  o.err = rltest::slurp(c.err_path);
  return o;
}

inline Outcome run(const std::vector<std::string>& args, const std::string& dir, unsigned long long address_space = 0,
                   std::chrono::milliseconds timeout = std::chrono::minutes(10)) {
  Child c = start(args, dir + "/out.txt", dir + "/err.txt", address_space);
  return wait(c, timeout);
}

// `rdsim train --quiet --config CONFIG --log-dir RUN` killed with SIGKILL `after` its first
// checkpoint.bin appeared (a crash mid-run); false when it ended before it could be killed.
inline bool kill_after_first_checkpoint(const std::string& config, const std::string& run, const std::string& dir,
                                        std::chrono::milliseconds after) {
  Child c = start({"train", "--quiet", "--config", config, "--log-dir", run}, dir + "/out.txt", dir + "/err.txt");
  while (running(c) && !std::filesystem::exists(run + "/checkpoint.bin")) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  std::this_thread::sleep_for(after);
  const bool alive = running(c);
  if (alive) ::kill(c.pid, SIGKILL);
  wait(c);
  return alive;
}

// kill_after_first_checkpoint, then `rdsim train --resume` of the killed run to its end; both must
// go as planned (the caller compares the logs with an uninterrupted run's).
inline void kill_and_resume(const std::string& config, const std::string& run, const rltest::ScratchDir& dir,
                            std::chrono::milliseconds after) {
  REQUIRE(kill_after_first_checkpoint(config, run, dir.path.string(), after));
  const auto r = rltest::run_rdsim("train --quiet --resume " + run, dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
}

}  // namespace proctest
