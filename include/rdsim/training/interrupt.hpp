#pragma once

// Ctrl-C and `kill` during training (src/training/interrupt.cpp). While an InterruptGuard lives, the
// first SIGINT or SIGTERM only records the request: the training loop finishes the update in
// progress, writes checkpoint.bin and model.bin, says how to resume and exits 130 (SIGINT) or
// 143 (SIGTERM). A second signal ends the process at once (exit 130/143): every file is replaced
// atomically, so the last complete checkpoint and model stay as they were.
namespace rdsim {

class InterruptGuard {
public:
  InterruptGuard();   // installs the handlers
  ~InterruptGuard();  // restores the previous ones
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // The signal that asked the run to stop (SIGINT or SIGTERM); 0 while none did.
  int requested() const;
  // The process exit status for that signal: 128 + its number.
  int exit_code() const { return 128 + requested(); }
};

}  // namespace rdsim
