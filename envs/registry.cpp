#include "rdsim/env_registry.hpp"

#include "rdsim/error.hpp"

namespace rdsim {

// Factories, one per environment file (declared here to keep env headers out of the registry).
std::unique_ptr<Env> make_cartpole(const EnvConfig& config);

const std::vector<EnvEntry>& env_registry() {
  static const std::vector<EnvEntry> entries = {
      {"cartpole", "Classic cart-pole balancing (Gym CartPole-v1 dynamics), Discrete(2)", false, make_cartpole},
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
