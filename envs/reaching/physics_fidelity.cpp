#include "rdsim/envs/reaching/physics_fidelity.hpp"

#include <algorithm>
#include <chrono>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/reaching/inmoov_tomato.hpp"
#include "rdsim/envs/reaching/jaka_button.hpp"
#include "rdsim/envs/reaching/jaka_obstacle.hpp"

namespace rdsim {

void original_solver_work(ReachTaskSpec& spec) {
  spec.world.solver_residual_threshold = 0.0;
  spec.world.sparse_joint_rows = false;
  spec.world.joint_row_warm_start = 0.0;
  spec.world.joint_block_solve = false;
  spec.world.mass_matrix_responses = false;
  spec.world.skip_separated_pairs = false;
  spec.world.warmstarting_factor = pybullet_solver(spec.world).warmstarting_factor;
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

void perturbed_original(ReachTaskSpec& spec) {
  original_solver_work(spec);
  spec.world.solver_iterations += 1;
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

std::vector<TrajectoryDeviation> trajectory_deviations(const EnvConfig& config, const SpecEdit& reference,
                                                       const std::vector<SpecEdit>& others,
                                                       const std::vector<int>& actions, std::uint64_t seed) {
  const std::unique_ptr<ReachEnv> a = make_reach_env(config, reference);
  if (!a->spec().action.discrete) throw Error("physics fidelity: " + config.name + ": expected Discrete actions");
  std::vector<std::unique_ptr<ReachEnv>> envs;
  for (const SpecEdit& edit : others) envs.push_back(make_reach_env(config, edit));
  std::uint64_t seed_a = seed;
  std::vector<std::uint64_t> seeds(envs.size(), seed);
  a->reset(seed);
  for (auto& e : envs) e->reset(seed);
  std::vector<TrajectoryDeviation> out(envs.size());
  double seconds_a = 0;
  for (int action : actions) {
    seconds_a += timed_step(*a, action, seed_a);
    const Eigen::VectorXf q_a = a->task().robot().joint_positions();
    for (size_t k = 0; k < envs.size(); ++k) {
      ReachEnv& b = *envs[k];
      TrajectoryDeviation& d = out[k];
      d.seconds_b += timed_step(b, action, seeds[k]);
      const double effector = (a->task().ee_position() - b.task().ee_position()).norm();
      int dof = 0;
      const double joint = (q_a - b.task().robot().joint_positions()).cwiseAbs().maxCoeff(&dof);
      if (joint > d.max_joint)
        d.max_joint_name = a->task().robot_model().joints[static_cast<size_t>(a->task().robot().dof_joint(dof))].name;
      d.mean_effector += effector;
      d.max_effector = std::max(d.max_effector, effector);
      d.mean_joint += joint;
      d.max_joint = std::max(d.max_joint, joint);
      ++d.steps;
    }
  }
  auto iterations = [](const ReachEnv& env) {
    const PhysicsWorld::Work w = env.task().world().work();
    return w.steps > 0 ? static_cast<double>(w.solver_iterations) / static_cast<double>(w.steps) : 0.0;
  };
  for (size_t k = 0; k < out.size(); ++k) {
    TrajectoryDeviation& d = out[k];
    d.iterations_a = iterations(*a);
    d.iterations_b = iterations(*envs[k]);
    d.seconds_a = seconds_a;
    if (d.steps > 0) {
      d.mean_effector /= d.steps;
      d.mean_joint /= d.steps;
    }
  }
  return out;
}

TrajectoryDeviation trajectory_deviation(const EnvConfig& config, const SpecEdit& edit_a, const SpecEdit& edit_b,
                                         const std::vector<int>& actions, std::uint64_t seed) {
  return trajectory_deviations(config, edit_a, {edit_b}, actions, seed)[0];
}

}  // namespace rdsim
