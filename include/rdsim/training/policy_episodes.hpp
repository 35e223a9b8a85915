#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/core/env.hpp"

// A policy run for whole episodes on one env: what `rdsim replay` prints and what a training run's
// evaluations (evaluation.hpp) record, the same episodes for the same model and seed.
namespace rdsim {

struct EpisodeOutcome {
  double episode_return = 0.0;
  long long length = 0;
  bool success = false;
};

struct PolicyEpisodeHooks {
  std::function<void(int episode)> on_start;  // episode from 0, after its reset
  // After every step: the episode's steps so far, its return so far, success so far, whether it ended.
  std::function<void(long long length, double episode_return, bool success, bool done)> on_step;
  std::function<void(int episode, const EpisodeOutcome&)> on_end;
};

// Runs `episodes` episodes of `algo`'s actions (the most likely ones when `deterministic`, else drawn
// from Rng::derive(seed, rng_stream::evaluation)): the first reset is seeded with `seed`, the others
// continue the env's own stream. An env without a step limit ends an episode after 1,000,000 steps.
std::vector<EpisodeOutcome> run_policy_episodes(Env& env, Algorithm& algo, int episodes, std::uint64_t seed,
                                                bool deterministic, const PolicyEpisodeHooks& hooks = {});

}  // namespace rdsim
