#pragma once
#include <cstddef>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/vecenv/vec_env.hpp"

// The collect step of the replay methods (DQN, SAC, TD3/DDPG): step every env once and hand each
// env's transition to the method's buffer.
namespace rdsim {

// Steps `envs` with `actions` (one per env) and calls add(i, observation, step, next_observation)
// for env i in order: the observation its action was chosen from, what the step gave, and the
// next state, which after an episode ended is the final observation (the env has already been
// reset). `prev` and `next` are scratch the caller keeps, so the hot loop reuses their storage.
template <class Add>
void step_transitions(VecEnv& envs, const std::vector<Action>& actions, std::vector<Observation>& prev,
                      Observation& next, Add&& add) {
  const int n = envs.size();
  // step() replaces the observations the actions were chosen from: keep them for the buffer.
  prev.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) envs.observations().copy_to(i, prev[static_cast<std::size_t>(i)]);
  const std::vector<EnvStep>& steps = envs.step(actions);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const EnvStep& s = steps[k];
    if (!s.done()) envs.observations().copy_to(i, next);
    add(i, prev[k], s, s.done() ? s.final_observation : next);
  }
}

}  // namespace rdsim
