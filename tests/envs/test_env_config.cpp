// Reading the "env" object of a config: the env's published defaults, strict keys, one set of rules.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "../error_of.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/obstacle_options.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

using Catch::Matchers::Contains;
using rdsim::test::error_of;
using rdsim::ConfigReader;

namespace {

rdsim::EnvConfig read(const char* text) {
  const auto json = nlohmann::json::parse(text);
  ConfigReader r(json, "x.json", "env");
  return rdsim::read_env_config(r);
}

}  // namespace

TEST_CASE("a mistyped env name names the env meant", "[config][suggest]") {
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_buton"})"); }),
             Contains("unknown environment \"jaka_buton\" (did you mean \"jaka_button\"?) (known: cartpole"));
  CHECK_THAT(error_of([] { read(R"({"name": "pong"})"); }), !Contains("did you mean"));
}

TEST_CASE("env config rejects a bad observation mode and unknown keys", "[config]") {
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_button", "observation": "pixels"})"); }),
             Contains("env.observation") && Contains("raw_pixels"));
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_button", "is_discret": true})"); }), Contains("env.is_discret"));
  auto c = read(R"({"name": "jaka_button", "observation": "raw_pixels", "max_steps": 50})");
  CHECK(c.observation == rdsim::ObservationMode::RawPixels);
  CHECK(c.max_steps == 50);
  CHECK(rdsim::to_json(c)["max_steps"] == 50);
}

TEST_CASE("every env publishes real defaults and a config is read over them", "[config]") {
  const auto button = read(R"({"name": "jaka_button"})");
  CHECK(button.get<rdsim::ReachOptions>().action_step == 0.015);
  CHECK(button.get<rdsim::ReachOptions>().success_threshold == 0.025);
  CHECK(button.get<rdsim::ReachOptions>().max_distance == 0.7);
  CHECK(button.max_steps == 200);
  const auto obstacle = read(R"({"name": "jaka_obstacle", "action_step": 0.01})");
  CHECK(obstacle.max_steps == 300);
  CHECK(obstacle.get<rdsim::ReachOptions>().max_distance == 0.9);
  CHECK(obstacle.get<rdsim::ReachOptions>().action_step == 0.01);
  const auto tomato = read(R"({"name": "inmoov_tomato"})");
  CHECK(tomato.get<rdsim::ReachOptions>().action_step == 0.004);
  CHECK(tomato.max_steps == 400);
  CHECK(read(R"({"name": "cartpole"})").max_steps == 500);
  // The resolved JSON records the values used, and reads back to the same config.
  const auto json = rdsim::to_json(tomato);
  CHECK(json["action_step"] == 0.004);
  ConfigReader again(json, "config.json", "env");
  CHECK(rdsim::to_json(rdsim::read_env_config(again)) == json);
}

TEST_CASE("env keys an env does not read are errors, and ranges hold for configs built in code", "[config]") {
  CHECK_THAT(error_of([] { read(R"({"name": "cartpole", "action_step": 0.01})"); }),
             Contains("env.action_step") && Contains("no effect on cartpole"));
  CHECK(rdsim::to_json(rdsim::default_env_config("cartpole")).size() == 4);  // name, observation, is_discrete, max_steps
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_button", "action_step": 0})"); }),
             Contains("env.action_step") && Contains("[0.0001, 2]"));
  CHECK_THAT(error_of([] { read(R"({"name": "no_such_env"})"); }), Contains("env.name") && Contains("jaka_button"));
  rdsim::EnvConfig zero = rdsim::default_env_config("jaka_button");
  zero.get<rdsim::ReachOptions>().action_step = 0.0;
  CHECK_THAT(error_of([&] { rdsim::make_env(zero); }), Contains("env.action_step"));
}

TEST_CASE("env.renderer is read, written back and checked", "[config][render]") {
  auto read = [](const nlohmann::json& env) {
    ConfigReader r(env, "test.json", "env");
    return rdsim::read_env_config(r);
  };
  CHECK(read({{"name", "jaka_button"}}).renderer == "osmesa");
  for (const char* choice : {"osmesa", "egl", "auto"}) {
    const rdsim::EnvConfig c = read({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"renderer", choice}});
    CHECK(c.renderer == choice);
    CHECK(read(rdsim::to_json(c)).renderer == choice);
  }
  CHECK_THROWS_WITH(read({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"renderer", "vulkan"}}),
                    Contains("test.json") && Contains("env.renderer") && Contains("vulkan"));
  // Without images to draw the key would do nothing.
  CHECK_THROWS_WITH(read({{"name", "jaka_button"}, {"renderer", "egl"}}),
                    Contains("env.renderer") && Contains("no effect"));
}

TEST_CASE("the paper-preset options: published per env, read only where they act", "[config]") {
  // Defaults that keep today's behaviour, with each env's own IK iterations.
  const auto button = read(R"({"name": "jaka_button"})");
  CHECK(button.get<rdsim::ReachOptions>().ik_iterations == 1);
  CHECK(button.get<rdsim::ReachOptions>().solver_iterations == 10);
  CHECK(button.get<rdsim::ReachOptions>().drive == rdsim::DriveMode::ComputedTorque);
  CHECK(button.get<rdsim::ReachOptions>().move_noise == 1.0 / 30.0);
  CHECK(button.get<rdsim::ReachOptions>().reset_noise == 0.02);
  CHECK(button.get<rdsim::ReachOptions>().end_on_success);
  CHECK(button.get<rdsim::ReachOptions>().workspace_bounds);
  CHECK(read(R"({"name": "inmoov_tomato"})").get<rdsim::ReachOptions>().ik_iterations == 3);
  // The column and its reward belong to jaka_obstacle alone.
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_button", "column_motion": "random_walk"})"); }),
             Contains("env.column_motion") && Contains("no effect on jaka_button"));
  CHECK_THAT(error_of([] { read(R"({"name": "inmoov_tomato", "reward": "inverse_distance"})"); }),
             Contains("env.reward") && Contains("no effect on inmoov_tomato"));
  const auto obstacle = read(R"({"name": "jaka_obstacle", "column_motion": "random_walk", "reward": "inverse_distance"})");
  CHECK(obstacle.get<rdsim::ObstacleOptions>().column_motion == rdsim::ColumnMotion::RandomWalk);
  CHECK(obstacle.get<rdsim::ObstacleOptions>().reward == rdsim::RewardRule::InverseDistance);
  CHECK_THAT(error_of([] { read(R"({"name": "cartpole", "solver_iterations": 150})"); }),
             Contains("no effect on cartpole"));
  // Choices and ranges are checked; the resolved JSON reads back to itself.
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_button", "drive": "servo"})"); }),
             Contains("env.drive") && Contains("position_motor"));
  CHECK_THAT(error_of([] { read(R"({"name": "jaka_button", "action_step": 2.5})"); }), Contains("env.action_step"));
  const auto json = rdsim::to_json(obstacle);
  CHECK(json["column_motion"] == "random_walk");
  ConfigReader again(json, "config.json", "env");
  CHECK(rdsim::to_json(rdsim::read_env_config(again)) == json);
}
