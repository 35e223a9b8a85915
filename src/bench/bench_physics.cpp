// `rdsim bench-physics`: each paper preset run over fixed action sequences twice in one process,
// with the solver's original work and with the speed-ups, interleaved step by step: how far the
// trajectories drift apart, and the speed ratio.
#include "rdsim/bench/bench_physics.hpp"

#include <algorithm>
#include <cstdio>

#include "rdsim/core/error.hpp"
#include "rdsim/envs/physics_fidelity.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {
namespace {

// The paper's tolerances on the mean end-effector deviation over a 1,000-step sequence (m).
double tolerance(const std::string& env) { return env.rfind("inmoov", 0) == 0 ? 0.01 : 0.005; }

}  // namespace

int bench_physics_command(const BenchPhysicsOptions& o) {
  const std::vector<std::string> envs = o.envs.empty() ? std::vector<std::string>{"jaka_button", "inmoov_tomato"} : o.envs;
  std::printf("rdsim bench-physics: paper preset, original solver work (a) vs the speed-ups (b), %d-step sequences\n",
              o.steps);
  std::printf("%-14s %-7s %4s %11s %11s %11s %11s %9s %8s  %s\n", "env", "script", "seed", "mean ee mm", "max ee mm",
              "mean q rad", "max q rad", "speed b/a", "within", "max q joint");
  bool all_within = true;
  for (const std::string& env : envs) {
    const EnvConfig config = read_train_config(repo_root() + "/configs/paper/" + env + ".json").env;
    double worst_mean = 0, seconds_a = 0, seconds_b = 0;
    for (ActionScript script : {ActionScript::Random, ActionScript::Sweeps}) {
      for (int seed = 1; seed <= o.seeds; ++seed) {
        const auto actions = action_sequence(script, static_cast<std::uint64_t>(seed), o.steps);
        const TrajectoryDeviation d =
            trajectory_deviation(config, original_solver_work, nullptr, actions, static_cast<std::uint64_t>(seed));
        const bool within = d.mean_effector <= tolerance(env);
        all_within &= within;
        worst_mean = std::max(worst_mean, d.mean_effector);
        seconds_a += d.seconds_a;
        seconds_b += d.seconds_b;
        std::printf("%-14s %-7s %4d %11.4f %11.4f %11.2e %11.2e %8.2fx %8s  %s\n", env.c_str(), to_string(script), seed,
                    1e3 * d.mean_effector, 1e3 * d.max_effector, d.mean_joint, d.max_joint, d.seconds_a / d.seconds_b,
                    within ? "yes" : "NO", d.max_joint_name.empty() ? "-" : d.max_joint_name.c_str());
        std::fflush(stdout);
      }
    }
    std::printf("%-14s all: worst mean ee %.4f mm (tolerance %.0f mm), speed b/a %.2fx\n", env.c_str(),
                1e3 * worst_mean, 1e3 * tolerance(env), seconds_a / seconds_b);
  }
  return all_within ? 0 : 1;
}

}  // namespace rdsim
