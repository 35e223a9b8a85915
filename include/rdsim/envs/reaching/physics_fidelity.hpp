#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"

// The fidelity gate of the physics speed-ups: a reaching env run twice over the same fixed action
// sequence, once with the solver doing all of its original work and once as configured (with the
// speed-ups of sim/physics_world.hpp WorldSettings and sim/robot.hpp RobotOptions), and how far
// the two trajectories drift apart. `rdsim bench-physics` prints it for the paper presets
// (configs/paper/); tests/envs/test_physics_fidelity.cpp holds it to the tolerances.
namespace rdsim {

// Edits a task's physics before the env is built.
using SpecEdit = std::function<void(ReachTaskSpec&)>;

// Every speed-up off: the work the solver did before they existed (all iterations, Bullet's dense
// joint rows, no early exit, no warm start, no welds). Leaves the physics the config asks for
// (iterations, drive, gains).
void original_solver_work(ReachTaskSpec& spec);
// The original work with one more solver iteration: a change far below any tolerance, whose
// deviation from the original shows how much a sequence amplifies tiny differences (a sweep that
// drives the arm through a singular pose or into the tree can turn a 1e-6 difference into another
// path). A sequence the original does not reproduce under it cannot judge a speed-up.
void perturbed_original(ReachTaskSpec& spec);

// jaka_button, jaka_obstacle or inmoov_tomato built from `config` with `edit` applied to its task
// (rdsim::Error for another env).
std::unique_ptr<ReachEnv> make_reach_env(const EnvConfig& config, const SpecEdit& edit);

// Fixed action sequences of the Discrete(6) moves (-x, +x, -y, +y, -z, +z):
//   random: each step a uniform move;
//   sweeps: a uniform move held for 10..60 steps, then another: long straight runs that reach the
//           workspace's edges, the joint limits and the objects (table, button, tree).
enum class ActionScript { Random, Sweeps };
const char* to_string(ActionScript script);
std::vector<int> action_sequence(ActionScript script, std::uint64_t seed, int steps);

struct TrajectoryDeviation {
  int steps = 0;
  double mean_effector = 0, max_effector = 0;  // m, |effector a - effector b| over the steps
  double mean_joint = 0, max_joint = 0;        // rad (m for prismatic), largest joint difference per step
  std::string max_joint_name;                  // the joint of max_joint
  double seconds_a = 0, seconds_b = 0;         // wall-clock time of each run (env steps only)
  double iterations_a = 0, iterations_b = 0;   // solver iterations per physics step of each run
};

// Runs the reference env (config + `reference`) and one env per edit in `others` from reset(seed)
// over `actions` (resetting each with seed + episode when an episode ends) and compares each
// other's end effector and joints with the reference's after every step. The runs are interleaved
// step by step, so their timings share the machine's load. One result per edit in `others`
// (seconds_a: the reference's time).
std::vector<TrajectoryDeviation> trajectory_deviations(const EnvConfig& config, const SpecEdit& reference,
                                                       const std::vector<SpecEdit>& others,
                                                       const std::vector<int>& actions, std::uint64_t seed);
TrajectoryDeviation trajectory_deviation(const EnvConfig& config, const SpecEdit& edit_a, const SpecEdit& edit_b,
                                         const std::vector<int>& actions, std::uint64_t seed);

}  // namespace rdsim
