#include <catch2/catch.hpp>

#include "env_test_util.hpp"
#include "rdsim/envs/reaching/physics_fidelity.hpp"

// The fidelity gate of the physics speed-ups (envs/physics_fidelity.hpp), short enough for CI;
// `rdsim bench-physics` runs the full 1,000-step sequences over several seeds.
using namespace rdsim;

TEST_CASE("Action sequences are fixed by their seed, sweeps hold each move", "[physics][fidelity]") {
  CHECK(action_sequence(ActionScript::Random, 3, 100) == action_sequence(ActionScript::Random, 3, 100));
  CHECK(action_sequence(ActionScript::Random, 3, 100) != action_sequence(ActionScript::Random, 4, 100));
  const std::vector<int> sweeps = action_sequence(ActionScript::Sweeps, 3, 500);
  REQUIRE(sweeps.size() == 500);
  int changes = 0;
  for (size_t i = 1; i < sweeps.size(); ++i) changes += sweeps[i] != sweeps[i - 1];
  CHECK(changes <= 500 / 10);
  for (int a : sweeps) CHECK((a >= 0 && a < 6));
}

TEST_CASE("The sparse joint rows alone leave a paper preset's trajectory unchanged", "[physics][fidelity]") {
  // Sparse rows: rdsim's joint motors and limits (src/sim/joint_rows.hpp) and solver rows, against
  // Bullet's constraints and dense rows.
  const SpecEdit sparse_only = [](ReachTaskSpec& s) {
    original_solver_work(s);
    s.world.sparse_joint_rows = true;
  };
  for (const auto& [name, steps] : {std::pair<const char*, int>{"inmoov_tomato", 60}, {"jaka_button", 1000}}) {
    INFO(name);
    for (ActionScript script : {ActionScript::Sweeps, ActionScript::Random}) {
      const TrajectoryDeviation d = trajectory_deviation(test::paper_env_config(name), original_solver_work, sparse_only,
                                                         action_sequence(script, 1, steps), 1);
      CHECK(d.steps == steps);
      CHECK(d.max_effector == 0.0);
      CHECK(d.max_joint == 0.0);
    }
  }
}

TEST_CASE("The physics speed-ups keep the Jaka paper preset within the fidelity tolerance", "[physics][fidelity]") {
  // Mean end-effector deviation from the run with the solver's original work <= 5 mm (the issue's
  // tolerance, there over 1,000 steps), on sequences the original reproduces under a tiny change
  // (one more solver iteration: perturbed_original).
  const EnvConfig config = test::paper_env_config("jaka_button");
  for (ActionScript script : {ActionScript::Random, ActionScript::Sweeps}) {
    const auto d = trajectory_deviations(config, original_solver_work, {nullptr, perturbed_original},
                                         action_sequence(script, 1, 300), 1);
    INFO(to_string(script) << ": mean " << d[0].mean_effector << " m, max " << d[0].max_effector
                           << " m, joints max " << d[0].max_joint << " rad (" << d[0].max_joint_name
                           << "); one more iteration: mean " << d[1].mean_effector << " m");
    REQUIRE(d[1].mean_effector <= 0.005);  // a sequence that can judge
    CHECK(d[0].steps == 300);
    CHECK(d[0].mean_effector <= 0.005);
  }
}

TEST_CASE("The physics speed-ups move the InMoov paper preset less than one more solver iteration does",
          "[physics][fidelity]") {
  // Under pybullet's solver settings (warm starting 0.1) 150 iterations do not converge the
  // InMoov's 54 position motors: one more iteration alone moves the palm 2-14 cm within 40-150
  // steps, so no sequence can judge a 1 cm tolerance (docs/benchmarks.md). What the speed-ups must
  // do instead: change the path by less, summed over the sequences, than that one iteration.
  const EnvConfig config = test::paper_env_config("inmoov_tomato");
  double speedups = 0, one_more_iteration = 0;  // m, summed mean palm deviations
  for (ActionScript script : {ActionScript::Random, ActionScript::Sweeps}) {
    for (std::uint64_t seed : {1, 2, 3}) {
      const auto d = trajectory_deviations(config, original_solver_work, {nullptr, perturbed_original},
                                           action_sequence(script, seed, 80), seed);
      CHECK(d[0].steps == 80);
      speedups += d[0].mean_effector;
      one_more_iteration += d[1].mean_effector;
    }
  }
  INFO("speed-ups " << speedups / 6 << " m, one more iteration " << one_more_iteration / 6 << " m (means)");
  CHECK(speedups < one_more_iteration);
}

TEST_CASE("Position-motor presets weld the InMoov's held joints, and only those", "[physics][fidelity]") {
  const std::unique_ptr<ReachEnv> fast = make_reach_env(test::paper_env_config("inmoov_tomato"), nullptr);
  const std::unique_ptr<ReachEnv> original = make_reach_env(test::paper_env_config("inmoov_tomato"), original_solver_work);
  fast->reset(1);
  original->reset(1);
  const ReachTask& t = fast->task();
  CHECK(t.robot().welded_dofs() == t.robot().dof() - t.chain().dof());  // 54 - 8
  CHECK(original->task().robot().welded_dofs() == 0);
  CHECK(t.robot().joint_positions() == original->task().robot().joint_positions());
  // The computed-torque default has nothing welded.
  const std::unique_ptr<ReachEnv> defaults = make_reach_env(test::env_config("inmoov_tomato"), nullptr);
  CHECK(defaults->task().robot().welded_dofs() == 0);
}

TEST_CASE("Two envs of a paper preset in one process step identically", "[physics][fidelity]") {
  // The InMoov frees welded joints near the tree, rebuilding its multibody and its constraints;
  // nothing the next steps compute may depend on where the allocator put the new objects.
  const EnvConfig config = test::paper_env_config("inmoov_tomato");
  for (std::uint64_t seed : {1, 2}) {
    const TrajectoryDeviation d = trajectory_deviation(config, nullptr, nullptr, action_sequence(ActionScript::Sweeps, seed, 1000), seed);
    INFO("seed " << seed);
    CHECK(d.steps == 1000);
    CHECK(d.max_effector == 0.0);
    CHECK(d.max_joint == 0.0);
  }
}

TEST_CASE("Skipping pairs that are provably apart leaves the paper presets' trajectories unchanged", "[physics][fidelity]") {
  const SpecEdit bullet_pairs = [](ReachTaskSpec& s) { s.world.skip_separated_pairs = false; };
  for (const char* env : {"jaka_button", "inmoov_tomato"}) {
    const EnvConfig config = test::paper_env_config(env);
    for (ActionScript script : {ActionScript::Random, ActionScript::Sweeps}) {
      const TrajectoryDeviation d = trajectory_deviation(config, bullet_pairs, nullptr, action_sequence(script, 1, 1000), 1);
      INFO(env << " " << to_string(script));
      CHECK(d.max_effector == 0.0);
      CHECK(d.max_joint == 0.0);
    }
  }
}
