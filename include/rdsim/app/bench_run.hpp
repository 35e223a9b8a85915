#pragma once
#include <cstdint>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// The timed loop shared by the benchmarks (bench-fps, bench-remote): random actions drawn
// before the clock starts, resets included, as an agent would see the env.
namespace rdsim {

Action random_action(const ActionSpace& space, Rng& rng);

double median(std::vector<double> v);
// The q-quantile (0..1) of `v` (nearest rank).
double quantile(std::vector<double> v, double q);

// Steps `env` `steps` times from reset(seed), resetting after each episode (counted in
// `episodes`). Returns steps per second. With `step_seconds`, each step's duration is appended.
double env_run(Env& env, long long steps, std::uint64_t seed, long long& episodes,
               std::vector<double>* step_seconds = nullptr);

}  // namespace rdsim
