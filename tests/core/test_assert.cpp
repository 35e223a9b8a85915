// RDSIM_ASSERT: a failed check prints where and what, then aborts, in every build type.
#include <catch2/catch.hpp>
#include <csignal>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "rdsim/core/assert.hpp"

namespace {

struct ChildEnd {
  int signal = 0;      // the signal that ended the child, 0 if it exited
  std::string stderr_text;
};

// Runs `f` in a forked child with stderr captured.
template <class F>
ChildEnd run_in_child(F f) {
  int fds[2];
  REQUIRE(pipe(fds) == 0);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    close(fds[0]);
    dup2(fds[1], STDERR_FILENO);
    f();
    _exit(0);
  }
  close(fds[1]);
  ChildEnd end;
  char buf[512];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) end.stderr_text.append(buf, static_cast<size_t>(n));
  close(fds[0]);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  if (WIFSIGNALED(status)) end.signal = WTERMSIG(status);
  return end;
}

int checked_half(int n) {
  RDSIM_ASSERT(n % 2 == 0, "checked_half needs an even number, got " + std::to_string(n));
  return n / 2;
}

}  // namespace

TEST_CASE("RDSIM_ASSERT aborts with file, line, condition and message", "[core][assert]") {
  const ChildEnd end = run_in_child([] { (void)checked_half(3); });
  CHECK(end.signal == SIGABRT);
  CHECK_THAT(end.stderr_text, Catch::Contains("test_assert.cpp:") && Catch::Contains("n % 2 == 0") &&
                                  Catch::Contains("checked_half needs an even number, got 3"));
}

TEST_CASE("RDSIM_ASSERT passes a true condition without evaluating the message", "[core][assert]") {
  int evaluated = 0;
  auto message = [&] {
    ++evaluated;
    return std::string("never");
  };
  RDSIM_ASSERT(checked_half(4) == 2, message());
  CHECK(evaluated == 0);
}
