#include "rdsim/demos/demo_fit.hpp"

#include <algorithm>

#include "rdsim/core/error.hpp"

namespace rdsim {

bool demo_neutral_env_key(const std::string& key) {
  static const char* const neutral[] = {"render_mode", "render_width", "render_height", "renderer",
                                        "urdf_root",   "random_target", "max_steps"};
  return std::any_of(std::begin(neutral), std::end(neutral), [&](const char* k) { return key == k; });
}

std::string demos_fit_problem(const nlohmann::json& file_env, const Spec& file_spec, const nlohmann::json& env_config,
                              const Spec& spec) {
  if (file_spec.env_name != spec.env_name)
    return "recorded on env " + file_spec.env_name + ", this env is " + spec.env_name;
  if (file_spec.observation.type != spec.observation.type || file_spec.observation.shape != spec.observation.shape)
    return "observations are " + describe_observation_space(file_spec.observation) + ", env " + spec.env_name + " has " +
           describe_observation_space(spec.observation);
  const ActionSpace &a = file_spec.action, &b = spec.action;
  const bool same_actions = a.discrete == b.discrete && (a.discrete ? a.n == b.n : a.low == b.low && a.high == b.high);
  if (!same_actions)
    return "actions are " + describe_action_space(a) + ", env " + spec.env_name + " has " + describe_action_space(b) +
           (a.discrete != b.discrete ? " (env.is_discrete differs)" : "");
  // Every option that changes what a step does must agree (action_step, success_threshold, ...).
  for (auto it = env_config.begin(); it != env_config.end(); ++it) {
    if (demo_neutral_env_key(it.key())) continue;
    const auto other = file_env.find(it.key());
    if (other == file_env.end() || *other != it.value())
      return "env." + it.key() + " is " + (other == file_env.end() ? std::string("not set") : other->dump()) +
             " in the demonstrations, " + it.value().dump() + " here";
  }
  for (auto it = file_env.begin(); it != file_env.end(); ++it)
    if (!demo_neutral_env_key(it.key()) && !env_config.contains(it.key()))
      return "env." + it.key() + " is " + it.value().dump() + " in the demonstrations, not set here";
  return "";
}

void check_demos_fit(const DemoFile& demos, const nlohmann::json& env_config, const Spec& spec) {
  const std::string problem = demos_fit_problem(demos.env_config, demos.spec, env_config, spec);
  if (!problem.empty()) throw Error(demos.path + ": these demonstrations do not fit the env: " + problem);
}

}  // namespace rdsim
