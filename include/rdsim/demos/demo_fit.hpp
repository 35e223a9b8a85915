#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/demos/demo_file.hpp"

// Whether demonstrations can teach an env: the one place that decides it (learning from a file,
// appending to a file).
namespace rdsim {

// Env options that do not change what an episode is: how frames for people are drawn, where the
// assets are, and the episode distribution (targets, step limit). Every other key must agree.
bool demo_neutral_env_key(const std::string& key);

// rdsim::Error naming the file when its episodes cannot be used with an env of `spec` whose
// resolved "env" object is `env_config`: another env, other observations, another action space
// ("actions are Discrete(6), env jaka_button has Box(3)"), or other task numbers (action_step, ...).
void check_demos_fit(const DemoFile& demos, const nlohmann::json& env_config, const Spec& spec);

// The same rule for two headers: a message naming the first difference, "" when they fit.
std::string demos_fit_problem(const nlohmann::json& file_env, const Spec& file_spec, const nlohmann::json& env_config,
                              const Spec& spec);

}  // namespace rdsim
