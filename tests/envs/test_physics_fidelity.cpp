#include <catch2/catch.hpp>

#include "env_test_util.hpp"
#include "rdsim/envs/physics_fidelity.hpp"

// The fidelity gate of the physics speed-ups (envs/physics_fidelity.hpp), short enough for CI;
// `rdsim bench-physics` runs the full 1,000-step sequences over several seeds.
using namespace rdsim;

TEST_CASE("Action sequences are fixed by their seed; sweeps hold each move", "[physics][fidelity]") {
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
  const EnvConfig config = test::paper_env_config("inmoov_tomato");
  const SpecEdit sparse_only = [](ReachTaskSpec& s) {
    original_solver_work(s);
    s.world.sparse_joint_rows = true;
  };
  const TrajectoryDeviation d = trajectory_deviation(config, original_solver_work, sparse_only,
                                                     action_sequence(ActionScript::Sweeps, 1, 60), 1);
  CHECK(d.steps == 60);
  CHECK(d.max_effector == 0.0);
  CHECK(d.max_joint == 0.0);
}

TEST_CASE("The physics speed-ups keep the paper presets within the fidelity tolerances", "[physics][fidelity]") {
  // Mean end-effector deviation from the run with the solver's original work: <= 5 mm for the Jaka,
  // <= 1 cm for the InMoov (the tolerances, there over 1,000 steps), on sequences the
  // original reproduces under a tiny change (one more solver iteration: perturbed_original).
  struct Case {
    const char* env;
    double tolerance;
    int steps;
  };
  for (const Case& c : {Case{"jaka_button", 0.005, 300}, Case{"inmoov_tomato", 0.01, 150}}) {
    const EnvConfig config = test::paper_env_config(c.env);
    for (ActionScript script : {ActionScript::Random, ActionScript::Sweeps}) {
      const auto d = trajectory_deviations(config, original_solver_work, {nullptr, perturbed_original},
                                           action_sequence(script, 1, c.steps), 1);
      INFO(c.env << " " << to_string(script) << ": mean " << d[0].mean_effector << " m, max " << d[0].max_effector
                 << " m, joints max " << d[0].max_joint << " rad (" << d[0].max_joint_name
                 << "); one more iteration: mean " << d[1].mean_effector << " m");
      REQUIRE(d[1].mean_effector <= c.tolerance);  // a sequence that can judge
      CHECK(d[0].steps == c.steps);
      CHECK(d[0].mean_effector <= c.tolerance);
    }
  }
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
