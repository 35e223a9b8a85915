#include "rdsim/training/interrupt.hpp"

#include <csignal>
#include <unistd.h>

namespace rdsim {
namespace {

volatile std::sig_atomic_t g_requested = 0;
struct sigaction g_previous_int, g_previous_term;

// Async-signal-safe: only write(2) and _exit(2).
void on_signal(int signal) {
  if (g_requested != 0) {
    constexpr char now[] = "\nrdsim: interrupted again: exiting now; the last checkpoint.bin and model.bin stay\n";
    (void)!::write(STDERR_FILENO, now, sizeof now - 1);
    ::_exit(128 + signal);
  }
  g_requested = signal;
  constexpr char soon[] =
      "\nrdsim: stopping after this update to save checkpoint.bin and model.bin (Ctrl-C again to quit at once)\n";
  (void)!::write(STDERR_FILENO, soon, sizeof soon - 1);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_requested = 0;
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // file I/O in progress carries on
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

int InterruptGuard::requested() const { return g_requested; }

}  // namespace rdsim
