#include "rdsim/env_registry.hpp"

#include "rdsim/error.hpp"

namespace rdsim {

// Factories, one per environment file (declared here to keep env headers out of the registry).

const std::vector<EnvEntry>& env_registry() {
  static const std::vector<EnvEntry> entries = {
  };
  return entries;
}

std::unique_ptr<Env> make_env(const EnvConfig& config) {
  std::string known;
  for (const auto& e : env_registry()) {
    if (e.name == config.name) return e.make(config);
    known += (known.empty() ? "" : ", ") + e.name;
  }
  throw Error("unknown environment \"" + config.name + "\" (known: " + known + ")");
}

}  // namespace rdsim
