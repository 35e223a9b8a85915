#include "rdsim/env_registry.hpp"

#include "rdsim/error.hpp"

namespace rdsim {

// Factories, one per environment file (declared here to keep env headers out of the registry).
std::unique_ptr<Env> make_cartpole(const EnvConfig& config);
std::unique_ptr<Env> make_jaka_button(const EnvConfig& config);
std::unique_ptr<Env> make_jaka_obstacle(const EnvConfig& config);
std::unique_ptr<Env> make_inmoov_tomato(const EnvConfig& config);

const std::vector<EnvEntry>& env_registry() {
  static const std::vector<EnvEntry> entries = {
      {"cartpole", "Classic cart-pole balancing (Gym CartPole-v1 dynamics), Discrete(2)", false, make_cartpole},
      {"jaka_button", "JAKA Zu 7 moves its flange to a button on a table by IK moves (RobotDrlSim 4.1)", true, make_jaka_button},
      {"jaka_obstacle", "jaka_button with a column to go around; -200 for touching it (RobotDrlSim 4.2)", true, make_jaka_obstacle},
      {"inmoov_tomato", "InMoov humanoid moves its right palm to a tomato on a tree by IK moves (RobotDrlSim 4.3)", true, make_inmoov_tomato},
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
