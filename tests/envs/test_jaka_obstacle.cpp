#include <catch2/catch.hpp>

#include "env_test_util.hpp"
#include "rdsim/envs/reaching/jaka_obstacle.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

// Spaces, bounds, determinism and truncation: tests/envs/test_env_contract.cpp.
using namespace rdsim;
using namespace rdsim::test;

namespace {

Eigen::Vector3f to_button(const Observation& o) { return to_target(o); }
Eigen::Vector3f flange(const Observation& o) { return o.values.segment<3>(6); }

// Greedy moves to a via point on the column's near side (between it and the robot base), then to the button.
struct Detour {
  bool via_reached = false;
  Action operator()(const Observation& o) {
    const Eigen::Vector3f via(0.25f, -0.05f, 0.12f);
    if (!via_reached && (via - flange(o)).norm() < 0.03f) via_reached = true;
    return greedy_action(via_reached ? to_button(o) : Eigen::Vector3f(via - flange(o)));
  }
};

}  // namespace

TEST_CASE("jaka_obstacle: observation and column placement", "[jaka_obstacle]") {
  JakaObstacle env(env_config("jaka_obstacle"));
  const Observation o = env.reset(0);
  const Eigen::Vector3f column = env.task().world().static_pose(env.task().static_body(JakaObstacle::column_index)).translation();
  CHECK((o.values.segment<3>(3) - (flange(o) - column)).norm() < 1e-6f);
  CHECK((flange(o) - env.task().ee_position()).norm() < 1e-6f);
  // The documented extras: the wrist links' origins from the column (they, not the flange, hit it).
  const RobotModel& model = env.task().robot_model();
  for (int k = 0; k < 2; ++k) {
    const int link = model.require_link(k == 0 ? "wrist_2_link" : "wrist_3_link");
    const Eigen::Vector3f wrist = env.task().robot().link_pose(link).translation();
    CHECK((o.values.segment<3>(9 + 3 * k) - (wrist - column)).norm() < 1e-6f);
  }
  // Nothing touches the column at home.
  for (int k = 0; k < 5; ++k) CHECK_FALSE(env.step(Action::discrete(k % 2 ? 4 : 5)).info.collision);
}

TEST_CASE("jaka_obstacle: the straight way hits the column", "[jaka_obstacle]") {
  for (bool random : {false, true}) {
    JakaObstacle env(env_config("jaka_obstacle", random));
    for (std::uint64_t seed = 0; seed < (random ? 4u : 1u); ++seed) {
      const auto e = run_episode(env, seed, [](const Observation& o) { return greedy_action(to_button(o)); });
      INFO("random " << random << " seed " << seed << " steps " << e.steps);
      CHECK(e.last.terminated);
      CHECK(e.last.info.collision);
      CHECK_FALSE(e.last.info.success);
      CHECK(e.last.reward == -200.0f);
    }
  }
}

TEST_CASE("jaka_obstacle: going round the column's near side reaches the button", "[jaka_obstacle]") {
  for (bool random : {false, true}) {
    JakaObstacle env(env_config("jaka_obstacle", random));
    for (std::uint64_t seed = 0; seed < (random ? 8u : 1u); ++seed) {
      const auto e = run_episode(env, seed, Detour{});
      INFO("random " << random << " seed " << seed << " steps " << e.steps << " d " << e.last.info.distance);
      CHECK(e.last.info.success);
      CHECK_FALSE(e.last.info.collision);
      const Eigen::Vector3f b = env.task().target();
      CHECK((b - Eigen::Vector3f(0.35f, 0.15f, b.z())).norm() >= 0.1f);  // button clear of the column
    }
  }
}

TEST_CASE("jaka_obstacle: bad config gives clear errors, raw pixels are 64x64x3", "[jaka_obstacle]") {
  EnvConfig c = env_config("jaka_obstacle");
  c.observation = ObservationMode::RawPixels;  // in detail: tests/envs/test_pixels.cpp
  CHECK(make_env(c)->spec().observation.shape == std::vector<int>{64, 64, 3});
  c = env_config("jaka_obstacle");
  c.get<ReachOptions>().action_step = -1;
  CHECK_THROWS_WITH(make_env(c), Catch::Contains("env.action_step"));
  // Config overrides reach the env.
  c = env_config("jaka_obstacle");
  c.max_steps = 17;
  CHECK(make_env(c)->spec().max_episode_steps == 17);
}
