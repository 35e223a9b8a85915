#include "rdsim/envs/physics_fidelity.hpp"

#include <algorithm>
#include <chrono>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/inmoov_tomato.hpp"
#include "rdsim/envs/jaka_button.hpp"
#include "rdsim/envs/jaka_obstacle.hpp"

namespace rdsim {

void original_solver_work(ReachTaskSpec& spec) {
  spec.world.solver_residual_threshold = 0.0;
  spec.world.sparse_joint_rows = false;
  spec.world.joint_row_warm_start = 0.0;
  spec.robot.weld_held_joints = false;
}

std::unique_ptr<ReachEnv> make_reach_env(const EnvConfig& config, const SpecEdit& edit) {
  ReachTaskSpec spec;
  ReachTerms terms;
  if (config.name == "jaka_button") {
    spec = jaka_button_spec(config);
    terms = jaka_button_terms();
  } else if (config.name == "jaka_obstacle") {
    spec = jaka_obstacle_spec(config);
    terms = jaka_obstacle_terms(config);
  } else if (config.name == "inmoov_tomato") {
    spec = inmoov_tomato_spec(config);
    terms = inmoov_tomato_terms(spec);
  } else {
    throw Error("physics fidelity: env: expected jaka_button, jaka_obstacle or inmoov_tomato, got '" + config.name + "'");
  }
  if (edit) edit(spec);
  return std::make_unique<ReachEnv>(std::move(spec), std::move(terms), config);
}

const char* to_string(ActionScript script) { return script == ActionScript::Random ? "random" : "sweeps"; }

std::vector<int> action_sequence(ActionScript script, std::uint64_t seed, int steps) {
  Rng rng(seed);
  std::vector<int> actions;
  actions.reserve(static_cast<size_t>(std::max(steps, 0)));
  while (static_cast<int>(actions.size()) < steps) {
    const int move = static_cast<int>(rng.below(6));
    const int hold = script == ActionScript::Random ? 1 : 10 + static_cast<int>(rng.below(51));
    for (int k = 0; k < hold && static_cast<int>(actions.size()) < steps; ++k) actions.push_back(move);
  }
  return actions;
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// One step of `env` (resetting it when the episode ends); returns its duration in seconds.
double timed_step(ReachEnv& env, int action, std::uint64_t& reset_seed) {
  const auto t0 = Clock::now();
  const StepResult r = env.step(Action::discrete(action));
  if (r.terminated || r.truncated) env.reset(++reset_seed);
  return seconds_since(t0);
}

}  // namespace

TrajectoryDeviation trajectory_deviation(const EnvConfig& config, const SpecEdit& edit_a, const SpecEdit& edit_b,
                                         const std::vector<int>& actions, std::uint64_t seed) {
  const std::unique_ptr<ReachEnv> a = make_reach_env(config, edit_a);
  const std::unique_ptr<ReachEnv> b = make_reach_env(config, edit_b);
  if (!a->spec().action.discrete) throw Error("physics fidelity: " + config.name + ": expected Discrete actions");
  std::uint64_t seed_a = seed, seed_b = seed;
  a->reset(seed);
  b->reset(seed);
  TrajectoryDeviation d;
  for (int action : actions) {
    d.seconds_a += timed_step(*a, action, seed_a);
    d.seconds_b += timed_step(*b, action, seed_b);
    const double effector = (a->task().ee_position() - b->task().ee_position()).norm();
    int dof = 0;
    const double joint =
        (a->task().robot().joint_positions() - b->task().robot().joint_positions()).cwiseAbs().maxCoeff(&dof);
    if (joint > d.max_joint) d.max_joint_name = a->task().robot_model().joints[static_cast<size_t>(a->task().robot().dof_joint(dof))].name;
    d.mean_effector += effector;
    d.max_effector = std::max(d.max_effector, effector);
    d.mean_joint += joint;
    d.max_joint = std::max(d.max_joint, joint);
    ++d.steps;
  }
  if (d.steps > 0) {
    d.mean_effector /= d.steps;
    d.mean_joint /= d.steps;
  }
  return d;
}

}  // namespace rdsim
