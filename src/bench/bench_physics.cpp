// `rdsim bench-physics`: each paper preset run over fixed action sequences in one process with the
// solver's original work (a), with the speed-ups (b) and with the original work plus one solver
// iteration (c, the sequence's own sensitivity), interleaved step by step: how far b and c drift
// from a, and the speed ratio of b to a.
#include "rdsim/bench/bench_physics.hpp"

#include <algorithm>
#include <cstdio>

#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/physics_fidelity.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {
namespace {

// The tolerances on the mean end-effector deviation over a 1,000-step sequence (m).
double tolerance(const std::string& env) { return env.rfind("inmoov", 0) == 0 ? 0.01 : 0.005; }

}  // namespace

int bench_physics_command(const BenchPhysicsOptions& o) {
  const std::vector<std::string> envs = o.envs.empty() ? std::vector<std::string>{"jaka_button", "inmoov_tomato"} : o.envs;
  std::printf("rdsim bench-physics: paper presets, %d-step sequences; a = the solver's original work, b = the "
              "speed-ups,\nc = a with one more solver iteration (how much the sequence itself amplifies a tiny change);\n"
              "iters a/b: solver iterations per physics step\n\n",
              o.steps);
  std::printf("%-14s %-7s %4s %12s %12s %12s %12s %10s %11s %12s %8s  %s\n", "env", "script", "seed", "b mean ee mm",
              "b max ee mm", "b mean q rad", "b max q rad", "speed b/a", "iters a/b", "c mean ee mm", "verdict",
              "b max q joint");
  bool all_within = true;
  for (const std::string& env : envs) {
    const EnvConfig config = read_train_config(repo_root() + "/configs/paper/" + env + ".json").env;
    double worst_mean = 0, seconds_a = 0, seconds_b = 0;
    int judged = 0, chaotic = 0;
    for (ActionScript script : {ActionScript::Random, ActionScript::Sweeps}) {
      for (int seed = 1; seed <= o.seeds; ++seed) {
        const auto actions = action_sequence(script, static_cast<std::uint64_t>(seed), o.steps);
        const auto d = trajectory_deviations(config, original_solver_work, {nullptr, perturbed_original}, actions,
                                             static_cast<std::uint64_t>(seed));
        const TrajectoryDeviation& b = d[0];
        const TrajectoryDeviation& c = d[1];
        // A sequence the original does not reproduce within the tolerance under c cannot judge b.
        const bool reproducible = c.mean_effector <= tolerance(env);
        const bool within = b.mean_effector <= tolerance(env);
        const char* verdict = within ? "within" : reproducible ? "OUTSIDE" : "chaotic";
        if (reproducible) {
          ++judged;
          all_within &= within;
          worst_mean = std::max(worst_mean, b.mean_effector);
        } else {
          ++chaotic;
        }
        seconds_a += b.seconds_a;
        seconds_b += b.seconds_b;
        char iterations[32];
        std::snprintf(iterations, sizeof iterations, "%.0f/%.1f", b.iterations_a, b.iterations_b);
        std::printf("%-14s %-7s %4d %12.4f %12.4f %12.2e %12.2e %9.2fx %11s %12.4f %8s  %s\n", env.c_str(),
                    to_string(script), seed, 1e3 * b.mean_effector, 1e3 * b.max_effector, b.mean_joint, b.max_joint,
                    b.seconds_a / b.seconds_b, iterations, 1e3 * c.mean_effector, verdict,
                    b.max_joint_name.empty() ? "-" : b.max_joint_name.c_str());
        std::fflush(stdout);
      }
    }
    std::printf("%-14s %d sequences judged (%d chaotic under c): worst b mean ee %.4f mm (tolerance %.0f mm); "
                "speed b/a over all %.2fx\n\n",
                env.c_str(), judged, chaotic, 1e3 * worst_mean, 1e3 * tolerance(env), seconds_a / seconds_b);
  }
  return all_within ? 0 : 1;
}

}  // namespace rdsim
