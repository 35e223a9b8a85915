#include "rdsim/core/process_owner.hpp"

#include <unistd.h>

#include "rdsim/core/error.hpp"

namespace rdsim {

ProcessOwner::ProcessOwner() : pid_(getpid()) {}

bool ProcessOwner::here() const { return getpid() == pid_; }

void ProcessOwner::require(const std::string& what) const {
  if (here()) return;
  throw Error(what + " was made in process " + std::to_string(pid_) + " and is used in process " +
              std::to_string(getpid()) + ", a fork of it: its worker threads and processes do not survive fork(). "
              "Make it in the process that uses it, or start child processes with spawn "
              "(multiprocessing.get_context(\"spawn\"), SubprocVecEnv(..., start_method=\"spawn\"))");
}

}  // namespace rdsim
