#pragma once
#include <string>
#include <vector>

// `rdsim bench-physics`: the fidelity gate of the physics speed-ups on the paper presets
// (src/bench/bench_physics.cpp; the comparison itself: envs/physics_fidelity.hpp).
namespace rdsim {

struct BenchPhysicsOptions {
  std::vector<std::string> envs;  // empty: jaka_button and inmoov_tomato
  int seeds = 3;                  // action sequences per script (random, sweeps), seeds 1..seeds
  int steps = 1000;               // env steps per sequence
};
int bench_physics_command(const BenchPhysicsOptions& options);

}  // namespace rdsim
