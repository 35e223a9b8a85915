#pragma once
#include <memory>
#include <string>
#include <vector>

#include "rdsim/env.hpp"
#include "rdsim/env_config.hpp"

namespace rdsim {

struct EnvEntry {
  std::string name;
  std::string description;
  bool supports_pixels = false;
  std::unique_ptr<Env> (*make)(const EnvConfig&);
};

// Every environment rdsim knows, listed explicitly in envs/registry.cpp (no static-init magic,
// so nothing silently disappears at link time).
const std::vector<EnvEntry>& env_registry();

// Creates the env named by config.name; rdsim::Error listing the known names otherwise.
std::unique_ptr<Env> make_env(const EnvConfig& config);

}  // namespace rdsim
