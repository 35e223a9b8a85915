#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/demos/demonstration.hpp"

// Appends episodes to a demonstration file (layout and crash safety: demo_file.hpp).
namespace rdsim {

class DemoWriter {
public:
  // Creates `path` holding no episode (written whole beside it, then linked to the name, so it
  // appears complete and never replaces another file), or with `append` continues an existing
  // file after reading it whole (read_demo_file) and checking that it holds the same env: same
  // spaces and task (check_demos_fit). A tail left by a write that a crash interrupted is cut off.
  // One writer at a time: the writer holds an exclusive lock (flock) on the file while it lives,
  // and a second one is refused at once ("another rdsim process is recording to this
  // demonstration file"); the kernel drops the lock when the process ends, however it ends.
  // rdsim::Error naming the file otherwise (also when it exists and `append` is false, or it is
  // not a regular file).
  DemoWriter(const std::string& path, const nlohmann::json& env_config, const Spec& spec, bool append);
  ~DemoWriter();
  DemoWriter(const DemoWriter&) = delete;
  DemoWriter& operator=(const DemoWriter&) = delete;

  // Validates the episode (validate_episode), writes and flushes it, then commits it. When this
  // returns the episode is on disk; rdsim::Error on a bad episode or a failed write.
  void append(const DemoEpisode& episode);

  long long episodes() const { return episodes_; }
  const std::string& path() const { return path_; }

private:
  void write_at(const std::string& bytes, unsigned long long offset);
  void sync();

  std::string path_;
  Spec spec_;
  int fd_ = -1;
  unsigned long long committed_ = 0;  // bytes
  long long episodes_ = 0;
};

}  // namespace rdsim
