#include "rdsim/envs/registry.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/envs/cartpole.hpp"
#include "rdsim/envs/inmoov_tomato.hpp"
#include "rdsim/envs/jaka_button.hpp"
#include "rdsim/envs/jaka_obstacle.hpp"
#include "rdsim/envs/pendulum.hpp"

namespace rdsim {
namespace {

// The options of every reaching env.
const std::vector<std::string>& reach_keys() {
  static const std::vector<std::string> keys = {
      "observation",   "is_discrete", "render_mode",       "multi_view",    "random_target", "max_distance",
      "urdf_root",     "max_steps",   "action_step",       "success_threshold", "action_repeat", "image_width",
      "image_height",  "render_width", "render_height",    "renderer"};
  return keys;
}

bool reads(const EnvEntry& entry, const std::string& key) {
  return key == "name" || std::find(entry.keys.begin(), entry.keys.end(), key) != entry.keys.end();
}

}  // namespace

const std::vector<EnvEntry>& env_registry() {
  static const std::vector<EnvEntry> entries = {
      {"cartpole", "Classic cart-pole balancing (Gym CartPole-v1 dynamics), Discrete(2)", false, cartpole_defaults,
       {"observation", "is_discrete", "max_steps"}, make_cartpole},
      {"pendulum", "Inverted pendulum swing-up (Gymnasium Pendulum-v1 dynamics), Box(1) torque", false,
       pendulum_defaults, {"observation", "is_discrete", "max_steps"}, make_pendulum},
      {"jaka_button", "JAKA Zu 7 moves its flange to a button on a table by IK moves (RobotDrlSim 4.1)", true,
       jaka_button_defaults, reach_keys(), make_jaka_button},
      {"jaka_obstacle", "jaka_button with a column to go around; -200 for touching it (RobotDrlSim 4.2)", true,
       jaka_obstacle_defaults, reach_keys(), make_jaka_obstacle},
      {"inmoov_tomato", "InMoov humanoid moves its right palm to a tomato on a tree by IK moves (RobotDrlSim 4.3)",
       true, inmoov_tomato_defaults, reach_keys(), make_inmoov_tomato},
  };
  return entries;
}

const EnvEntry& env_entry(const std::string& name) {
  std::string known;
  for (const auto& e : env_registry()) {
    if (e.name == name) return e;
    known += (known.empty() ? "" : ", ") + e.name;
  }
  throw Error("unknown environment \"" + name + "\" (known: " + known + ")");
}

EnvConfig default_env_config(const std::string& name) {
  const EnvEntry& entry = env_entry(name);
  EnvConfig c = entry.defaults();
  c.name = entry.name;
  return c;
}

EnvConfig read_env_config(ConfigReader& r) {
  std::string name;
  r.read("name", name);
  if (name.empty()) r.fail("name", "expected an environment name (see `rdsim envs`)");
  const EnvEntry* entry = nullptr;
  try {
    entry = &env_entry(name);
  } catch (const Error& e) {
    r.fail("name", e.what());
  }
  // Keys EnvConfig declares but this env does not read would silently do nothing.
  static const nlohmann::json declared = config::write_fields(EnvConfig{});
  for (const auto& key : r.keys()) {
    if (declared.contains(key) && !reads(*entry, key)) {
      std::string list;
      for (const auto& k : entry->keys) list += ", " + k;
      r.fail(key, "has no effect on " + name + " (it reads: name" + list + ")");
    }
  }
  EnvConfig c = default_env_config(name);
  config::read_fields(r, c);
  return c;
}

nlohmann::json to_json(const EnvConfig& config) {
  const EnvEntry& entry = env_entry(config.name);
  nlohmann::json all = config::write_fields(config), out = nlohmann::json::object();
  for (auto it = all.begin(); it != all.end(); ++it)
    if (reads(entry, it.key())) out[it.key()] = it.value();
  return out;
}

std::unique_ptr<Env> make_env(const EnvConfig& config) {
  const EnvEntry& entry = env_entry(config.name);
  // The same rules as a config file: write the values out and read them back.
  const nlohmann::json json = to_json(config);
  ConfigReader reader(json, config.name, "env");
  (void)read_env_config(reader);
  return entry.make(config);
}

}  // namespace rdsim
