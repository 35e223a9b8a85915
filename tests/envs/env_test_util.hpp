#pragma once
#include <Eigen/Core>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

// Helpers shared by the env tests.
namespace rdsim::test {

inline EnvConfig env_config(const std::string& name, bool random_target = false) {
  EnvConfig c = rdsim::default_env_config(name);
  if (auto* reach = c.find<ReachOptions>()) reach->random_target = random_target;
  return c;
}

// The "env" object of the paper preset configs/paper/<name>[_pixels].json, read as a config's.
inline EnvConfig paper_env_config(const std::string& name, bool pixels = false) {
  const std::string path = repo_root() + "/configs/paper/" + name + (pixels ? "_pixels" : "") + ".json";
  const nlohmann::json env = nlohmann::json::parse(read_file(path)).at("env");
  ConfigReader reader(env, path, "env");
  return read_env_config(reader);
}

// The first three values of a reaching env's ground-truth observation: target - end effector.
inline Eigen::Vector3f to_target(const Observation& o) { return o.values.head<3>(); }

// Discrete(6) move along the largest component of `to_target` (-x, +x, -y, +y, -z, +z).
inline Action greedy_action(const Eigen::Vector3f& to_target) {
  int axis = 0;
  to_target.cwiseAbs().maxCoeff(&axis);
  return Action::discrete(2 * axis + (to_target[axis] > 0.0f ? 1 : 0));
}

struct EpisodeEnd {
  StepResult last;
  int steps = 0;
  float total_reward = 0.0f;
};

// Runs `policy(observation) -> Action` until the episode ends.
template <class Policy>
EpisodeEnd run_episode(Env& env, std::uint64_t seed, Policy&& policy) {
  EpisodeEnd e;
  Observation obs = env.reset(seed);
  for (;;) {
    e.last = env.step(policy(obs));
    obs = e.last.observation;
    ++e.steps;
    e.total_reward += e.last.reward;
    if (e.last.terminated || e.last.truncated) return e;
  }
}

}  // namespace rdsim::test
