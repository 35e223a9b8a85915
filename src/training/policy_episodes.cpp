#include "rdsim/training/policy_episodes.hpp"

#include <utility>

#include "rdsim/core/rng.hpp"

namespace rdsim {

std::vector<EpisodeOutcome> run_policy_episodes(Env& env, Algorithm& algo, int episodes, std::uint64_t seed,
                                                bool deterministic, const PolicyEpisodeHooks& hooks) {
  Rng rng = Rng::derive(seed, rng_stream::evaluation);
  // Environments without a step limit still end: a policy that never fails stops here.
  const long long step_cap = env.spec().max_episode_steps > 0 ? env.spec().max_episode_steps : 1'000'000;
  std::vector<EpisodeOutcome> outcomes;
  outcomes.reserve(static_cast<std::size_t>(episodes));
  for (int k = 0; k < episodes; ++k) {
    Observation obs = k == 0 ? env.reset(seed) : env.reset();
    if (hooks.on_start) hooks.on_start(k);
    EpisodeOutcome e;
    for (bool done = false; !done && e.length < step_cap;) {
      StepResult r = env.step(algo.act(obs, deterministic, rng));
      e.episode_return += r.reward;
      ++e.length;
      e.success = e.success || r.info.success;
      done = r.terminated || r.truncated;
      obs = std::move(r.observation);
      if (hooks.on_step) hooks.on_step(e.length, e.episode_return, e.success, done || e.length >= step_cap);
    }
    if (hooks.on_end) hooks.on_end(k, e);
    outcomes.push_back(e);
  }
  return outcomes;
}

}  // namespace rdsim
