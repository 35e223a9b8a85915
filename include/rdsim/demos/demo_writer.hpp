#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/demos/demonstration.hpp"

// Appends episodes to a demonstration file (layout and crash safety: demo_file.hpp).
namespace rdsim {

class DemoWriter {
public:
  // Creates `path` holding no episode (written atomically), or with `append` continues an existing
  // file after reading it whole (read_demo_file) and checking that it holds the same env: same
  // spaces and task (check_demos_fit). A tail left by a write that a crash interrupted is cut off.
  // rdsim::Error naming the file otherwise (also when it exists and `append` is false).
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
