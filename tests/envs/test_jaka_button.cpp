#include <catch2/catch.hpp>
#include <cstring>
#include <limits>

#include "env_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/jaka_button.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

// Spaces, bounds, determinism and truncation: tests/envs/test_env_contract.cpp.
using namespace rdsim;
using namespace rdsim::test;

namespace {

// The target point read back from the physics world: top of the button body.
Eigen::Vector3f button_top(const JakaButton& env) {
  const ReachTask& t = env.task();
  return t.world().static_pose(t.static_body(JakaButton::button_index)) * Eigen::Vector3f(0.0f, 0.0f, 0.03f);
}

}  // namespace

TEST_CASE("jaka_button: reward is minus the flange-button distance", "[jaka_button]") {
  JakaButton env(env_config("jaka_button", true));
  env.reset(5);
  Rng actions(1);
  for (int k = 0; k < 50; ++k) {
    const StepResult r = env.step(Action::discrete(static_cast<int>(actions.below(6))));
    const ReachTask& t = env.task();
    const Eigen::Vector3f flange = t.robot().link_pose(t.robot_model().require_link("flange_link")).translation();
    const float d = (flange - button_top(env)).norm();
    CHECK(r.reward == Approx(-d).margin(1e-6));
    CHECK(r.info.distance == Approx(d).margin(1e-6));
    CHECK((to_target(r.observation) - (button_top(env) - flange)).norm() < 1e-6f);
    if (r.terminated || r.truncated) env.reset();
  }
}

TEST_CASE("jaka_button: a greedy policy presses the button, fixed and random targets", "[jaka_button]") {
  auto greedy = [](const Observation& o) { return greedy_action(to_target(o)); };
  JakaButton fixed(env_config("jaka_button"));
  const auto e = run_episode(fixed, 1, greedy);
  CHECK(e.last.terminated);
  CHECK(e.last.info.success);
  CHECK_FALSE(e.last.info.out_of_bounds);
  CHECK(e.steps < 200);
  CHECK(fixed.task().target().isApprox(Eigen::Vector3f(0.5f, 0.0f, 0.03f)));

  JakaButton random(env_config("jaka_button", true));
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
  for (std::uint64_t seed = 0; seed < 12; ++seed) {
    const auto r = run_episode(random, seed, greedy);
    INFO("seed " << seed << " steps " << r.steps << " distance " << r.last.info.distance);
    CHECK(r.last.info.success);
    lo = lo.cwiseMin(random.task().target());
    hi = hi.cwiseMax(random.task().target());
  }
  // The targets really are spread over the paper's box.
  CHECK(hi.x() - lo.x() > 0.1f);
  CHECK(hi.y() - lo.y() > 0.2f);
  CHECK(lo.x() >= 0.35f - 1e-6f);
  CHECK(hi.x() <= 0.65f + 1e-6f);
  CHECK(lo.y() >= -0.3f - 1e-6f);
  CHECK(hi.y() <= 0.3f + 1e-6f);
}

TEST_CASE("jaka_button: continuous actions move the flange", "[jaka_button]") {
  EnvConfig c = env_config("jaka_button", true);
  c.is_discrete = false;
  auto env = make_env(c);
  CHECK_FALSE(env->spec().action.discrete);
  CHECK(env->spec().action.dim() == 3);
  // Proportional control: full-scale moves toward the button.
  const auto e = run_episode(*env, 3, [](const Observation& o) {
    const Eigen::Vector3f d = to_target(o);
    return Action::continuous((d / std::max(d.cwiseAbs().maxCoeff(), 1e-6f)).eval());
  });
  CHECK(e.last.info.success);
  CHECK_THROWS_AS(env->step(Action::continuous(Eigen::VectorXf::Zero(2))), Error);
}

TEST_CASE("jaka_button: leaving the workspace ends the episode with a penalty", "[jaka_button]") {
  EnvConfig c = env_config("jaka_button");
  c.get<ReachOptions>().max_distance = 0.35;  // m: moving sideways gets there long before the step limit
  auto env = make_env(c);
  const auto e = run_episode(*env, 2, [](const Observation&) { return Action::discrete(3); });  // +y
  CHECK(e.last.terminated);
  CHECK(e.last.info.out_of_bounds);
  CHECK_FALSE(e.last.info.success);
  CHECK(e.last.info.distance > 0.35f);
  // Penalty: what staying at max_distance for the remaining steps would have cost.
  CHECK(e.last.reward == Approx(-e.last.info.distance - 0.35f * (200 - e.steps)).epsilon(1e-4));
}

TEST_CASE("jaka_button: bad config values name their key", "[jaka_button]") {
  EnvConfig c = env_config("jaka_button");
  c.get<ReachOptions>().action_step = -0.01;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.action_step"));
  c = env_config("jaka_button");
  c.get<ReachOptions>().success_threshold = -1;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.success_threshold"));
  c = env_config("jaka_button");
  c.max_steps = -5;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.max_steps"));
  c = env_config("jaka_button");
  c.get<ReachOptions>().urdf_root = "/nonexistent";
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("/nonexistent"));
  auto env = make_env(env_config("jaka_button"));
  env->reset(0);
  CHECK_THROWS_WITH(env->step(Action::discrete(6)), Catch::Contains("0..5"));
}

TEST_CASE("jaka_button: the world's settings keep the table solid", "[jaka_button]") {
  // The env's physics (10 solver iterations, ComputedTorque drive, no limit rows) with the workspace
  // floor lowered below the table top, and the flange driven down into the table.
  ReachTaskSpec spec = jaka_button_spec(env_config("jaka_button"));
  spec.workspace.min().z() = -0.2f;
  spec.move_noise = 0.0f;
  ReachTask task(spec);
  Rng rng(0);
  task.reset(rng, false);
  task.set_target(Eigen::Vector3f(0.7f, 0.3f, 0.03f));  // button out of the way
  const int table = task.static_body(0);
  float lowest = 1.0f;
  for (int k = 0; k < 150; ++k) {
    task.apply_move(Eigen::Vector3f(-0.02f, 0.0f, -0.015f) * (k < 10 ? 1.0f : 0.0f) +
                        Eigen::Vector3f(0.0f, 0.0f, -0.015f),
                    rng);
    task.step_physics();
    lowest = std::min(lowest, task.ee_position().z());
  }
  CHECK(task.world().touching({task.robot().body(), -1}, {table, -1}));
  CHECK(lowest > -0.01f);  // the table top is z = 0: at most a centimetre of penetration
}

TEST_CASE("jaka_button: button paper is the original's free button: the arm pushes it away, the target moves with it, "
          "a saved state restores it", "[jaka_button]") {
  EnvConfig config = env_config("jaka_button");
  config.get<ButtonOptions>().button = ButtonBody::Paper;
  config.get<ReachOptions>().end_on_success = false;  // touching the button is a success: keep pushing
  JakaButton env(config), restored(config);
  const Eigen::Vector3f start(0.5f, 0.0f, 0.0f);  // the original's target: under its button
  env.reset(3);
  CHECK(env.task().target().isApprox(start));
  const auto flange = [](const JakaButton& e) -> Eigen::Vector3f {  // a copy: link_pose is a temporary
    return e.task().robot().link_pose(e.task().robot_model().require_link("flange_link")).translation();
  };
  // Beside the button (it spans y -0.1..0.1), down to the workspace floor, then into it along +y.
  const auto move = [&](int action, int steps) {
    StepResult r;
    for (int k = 0; k < steps; ++k) r = env.step(Action::discrete(action));
    return r;
  };
  move(2, 25);  // -y
  INFO("flange before the descent " << flange(env).transpose());
  CHECK((env.task().target() - start).norm() < 1e-3f);  // it rests on the table, untouched
  const StepResult down = move(4, 40);  // -z
  INFO("flange at the floor " << flange(env).transpose() << " ended " << down.terminated << down.truncated);
  move(3, 10);  // +y, into the button
  env.drop_caches();  // as a checkpoint does (core/env_state.hpp)
  const std::string saved = env.save_state();
  restored.reset(11);
  restored.load_state(saved, "test");
  CHECK(restored.save_state() == saved);
  // A state without the button's motion (rdsim's static button) or with a damaged pose: one clear error.
  JakaButton fixed(env_config("jaka_button"));
  fixed.reset(3);
  CHECK_THROWS_WITH(restored.load_state(fixed.save_state(), "static.bin"), Catch::Contains("static.bin"));
  const ReachTask& task = restored.task();
  const FreeBodyState motion = task.world().free_body_state(task.static_body(JakaButton::button_index));
  const std::string pose_bytes(reinterpret_cast<const char*>(motion.transform), sizeof motion.transform);
  std::string damaged = saved;
  const size_t at = damaged.find(pose_bytes);
  REQUIRE(at != std::string::npos);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(damaged.data() + at, &nan, sizeof nan);
  CHECK_THROWS_WITH(restored.load_state(damaged, "damaged.bin"),
                    Catch::Contains("damaged.bin: env state holds a free body pose that is not finite"));
  restored.load_state(saved, "test");
  StepResult a, b;
  for (int k = 0; k < 40; ++k) {
    a = env.step(Action::discrete(3));
    b = restored.step(Action::discrete(3));
    REQUIRE(a.observation.values == b.observation.values);
    REQUIRE(a.reward == b.reward);
  }
  INFO("flange after the push " << flange(env).transpose() << ", target " << env.task().target().transpose());
  CHECK(env.task().target().y() > start.y() + 0.02f);  // pushed away by more than 2 cm
  CHECK((to_target(a.observation) - (env.task().target() - flange(env))).norm() < 1e-5f);
  CHECK(a.reward == Approx(-(env.task().target() - flange(env)).norm()).margin(1e-6));
  env.reset(3);
  CHECK(env.task().target().isApprox(start));
  // Off the table's edge (x 0.95) the original's floor plane, at the table top's height, carries it.
  config.get<ReachOptions>().workspace_bounds = false;  // a far button would end the episode
  JakaButton far(config);
  far.reset(3);
  const Eigen::Vector3f beyond(1.3f, 0.2f, 0.0f);
  far.task().set_target(beyond);
  for (int k = 0; k < 100; ++k) REQUIRE_FALSE(far.step(Action::discrete(4)).terminated);
  CHECK((far.task().target() - beyond).norm() < 2e-3f);
}
