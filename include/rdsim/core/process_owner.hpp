#pragma once
#include <sys/types.h>

#include <string>

// The process that made an object owning threads or child processes (a worker pool, env worker
// processes, the Python binding's helper thread). fork() copies the object but not its threads, and
// the children belong to the parent: in a forked process the object must not be used (its calls
// would wait forever for threads that are not there) and its destructor must leave the parent's
// threads and children alone.
namespace rdsim {

class ProcessOwner {
public:
  ProcessOwner();
  // True in the process that made the object; false in a fork of it.
  bool here() const;
  // rdsim::Error naming `what` when not here(): one clear message instead of a hang.
  void require(const std::string& what) const;

private:
  pid_t pid_;
};

}  // namespace rdsim
