// The teleoperation session without a window: moves, RobotControl steps, recording, and the scene
// the window draws.
#include <catch2/catch.hpp>
#include <filesystem>
#include <set>

#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/envs/manipulation/manipulation_env.hpp"
#include "rdsim/envs/manipulation/manipulation_expert.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/teleop/scene_mirror.hpp"
#include "rdsim/teleop/teleop_session.hpp"
#include "../scratch_dir.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;

namespace {

EnvConfig button_config() {
  EnvConfig c = default_env_config("jaka_button");
  c.get<ReachOptions>().random_target = true;
  return c;
}

}  // namespace

TEST_CASE("keyboard moves are the env's own actions", "[teleop]") {
  ActionSpace discrete;
  discrete.n = 6;
  CHECK(move_action(Move::MinusX, discrete).index == 0);
  CHECK(move_action(Move::PlusZ, discrete).index == 5);
  ActionSpace box;
  box.discrete = false;
  box.low = Eigen::VectorXf::Constant(3, -1.0f);
  box.high = Eigen::VectorXf::Constant(3, 1.0f);
  CHECK(move_action(Move::MinusY, box).values == Eigen::Vector3f(0.0f, -1.0f, 0.0f));
  CHECK(move_action(Move::PlusX, box).values == Eigen::Vector3f(1.0f, 0.0f, 0.0f));
  ActionSpace two;
  two.n = 2;
  CHECK_THROWS_WITH(move_action(Move::PlusX, two), Contains("Discrete(6), Box(3) or Box(4)"));
  ActionSpace fingers = box;  // the manipulation tasks: moves and the fingers' opening
  fingers.low = Eigen::VectorXf::Constant(4, -1.0f);
  fingers.high = Eigen::VectorXf::Constant(4, 1.0f);
  CHECK(move_action(Move::PlusZ, fingers, -1.0f).values == Eigen::Vector4f(0.0f, 0.0f, 1.0f, -1.0f));
}

TEST_CASE("the gripper key closes and opens the fingers, recorded as the env's own actions", "[teleop][demos]") {
  test::ScratchDir dir("teleop_gripper");
  const EnvConfig config = default_env_config("pick_and_place");
  auto env = make_env(config);
  const nlohmann::json env_json = to_json(config);
  DemoWriter writer(dir / "g.demo", env_json, env->spec(), true);
  TeleopSession session(*env, 7, &writer, env_json);
  REQUIRE(session.status().has_gripper);
  CHECK(session.status().gripper_open);
  session.start_recording();
  CHECK(session.act(Move::MinusZ));
  CHECK(session.toggle_gripper());
  CHECK_FALSE(session.status().gripper_open);
  for (int k = 0; k < 8; ++k) session.act(Move::PlusX);  // moves keep the fingers closing
  const RobotSnapshot s = session.control().robot_state();
  CHECK(s.joint_positions[6] + s.joint_positions[7] < 0.005f);  // the fingers' opening, m
  session.stop_recording();
  const DemoFile file = read_demo_file(dir / "g.demo");
  REQUIRE(file.episodes.size() == 1u);
  const DemoEpisode& e = file.episodes[0];
  REQUIRE(e.steps() == 10);
  CHECK(e.actions[0].values[3] == 1.0f);   // open
  CHECK(e.actions[1].values == Eigen::Vector4f(0.0f, 0.0f, 0.0f, -1.0f));  // the gripper key
  CHECK(e.actions[9].values[3] == -1.0f);  // still closed
  // An env without fingers in its actions: no gripper key.
  auto button = make_env(button_config());
  TeleopSession plain(*button, 1, nullptr, to_json(button_config()));
  CHECK_FALSE(plain.status().has_gripper);
  CHECK_THROWS_WITH(plain.toggle_gripper(), Contains("has no gripper"));
}

TEST_CASE("a teleop session records what the person did as a demonstration of the env's actions", "[teleop][demos]") {
  test::ScratchDir dir("teleop_session");
  const EnvConfig config = button_config();
  auto env = make_env(config);
  const nlohmann::json env_json = to_json(config);
  DemoWriter writer(dir / "h.demo", env_json, env->spec(), true);
  TeleopSession session(*env, 40, &writer, env_json);
  CHECK(session.status().steps == 0);

  // Driving without recording: nothing is written.
  CHECK(session.act(move_action(Move::MinusZ, env->spec().action)));
  CHECK(session.move_effector(Eigen::Vector3f(0.45f, 0.0f, 0.2f)));
  CHECK(session.status().steps == 2);
  CHECK(session.status().info.distance > 0.0f);

  // Record: a fresh episode (the next seed), keys only, saved on Stop.
  session.start_recording();
  CHECK(session.status().recording);
  CHECK(session.status().steps == 0);
  CHECK_THROWS_WITH(session.move_effector(Eigen::Vector3f(0.4f, 0.0f, 0.2f)), Contains("while recording"));
  for (Move m : {Move::MinusZ, Move::MinusZ, Move::PlusX, Move::MinusY}) session.act(move_action(m, env->spec().action));
  CHECK(session.status().recorded_steps == 4);
  session.stop_recording();
  CHECK_FALSE(session.status().recording);
  CHECK(session.status().saved_episodes == 1);
  CHECK_THAT(session.status().message, Contains("saved episode 1: 4 steps"));

  // Discard drops a recording; Reset too.
  session.start_recording();
  session.act(move_action(Move::PlusZ, env->spec().action));
  session.discard_recording();
  session.start_recording();
  session.reset();
  CHECK_FALSE(session.status().recording);
  session.start_recording();
  session.stop_recording();  // no step: nothing saved
  CHECK(writer.episodes() == 1);

  const DemoFile f = read_demo_file(dir / "h.demo");
  REQUIRE(f.episodes.size() == 1);
  const DemoEpisode& e = f.episodes[0];
  CHECK(e.source == DemoSource::Human);
  CHECK(e.seed == std::optional<std::uint64_t>(41));  // episode 0 had seed 40
  CHECK(e.steps() == 4);
  CHECK(e.actions[0].index == 4);
  CHECK(e.actions[2].index == 1);
  CHECK(e.actions[3].index == 2);
  CHECK_FALSE(e.ended());  // stopped by the person

  // The demonstration replays: its actions from its seed give its observations.
  auto replay = make_env(config);
  CHECK(replay->reset(*e.seed).values == e.observations[0].values);
  for (int t = 0; t < e.steps(); ++t)
    CHECK(replay->step(e.actions[static_cast<size_t>(t)]).observation.values == e.observations[static_cast<size_t>(t) + 1].values);
}

TEST_CASE("an episode the env ends while recording is saved at once", "[teleop][demos]") {
  test::ScratchDir dir("teleop_session");
  EnvConfig config = button_config();
  config.max_steps = 5;
  auto env = make_env(config);
  const nlohmann::json env_json = to_json(config);
  DemoWriter writer(dir / "t.demo", env_json, env->spec(), true);
  TeleopSession session(*env, 0, &writer, env_json);
  session.start_recording();
  for (int k = 0; k < 7; ++k) session.act(move_action(Move::PlusZ, env->spec().action));
  CHECK(session.status().ended);
  CHECK(session.status().truncated);
  CHECK_FALSE(session.status().recording);
  CHECK_FALSE(session.act(move_action(Move::PlusZ, env->spec().action)));  // over until Reset
  const DemoFile f = read_demo_file(dir / "t.demo");
  REQUIRE(f.episodes.size() == 1);
  CHECK(f.episodes[0].steps() == 5);
  CHECK(f.episodes[0].truncated);
}

TEST_CASE("without a demonstration file there is nothing to record into", "[teleop]") {
  auto env = make_env(button_config());
  TeleopSession session(*env, 0, nullptr, to_json(button_config()));
  CHECK_FALSE(session.can_record());
  CHECK_THROWS_WITH(session.start_recording(), Contains("rdsim teleop --record FILE"));
  auto cartpole = make_env(default_env_config("cartpole"));
  CHECK_THROWS_WITH(TeleopSession(*cartpole, 0, nullptr, nlohmann::json::object()), Contains("cannot be driven by hand"));
}

TEST_CASE("the window's scene mirror poses the robot as the env has it", "[teleop]") {
  for (const char* name : {"jaka_obstacle", "inmoov_tomato"}) {
    INFO(name);
    EnvConfig config = default_env_config(name);
    config.get<ReachOptions>().random_target = true;
    auto env = make_env(config);
    env->reset(3);
    auto& reach = dynamic_cast<ReachEnv&>(*env);
    for (int k = 0; k < 20; ++k) env->step(Action::discrete(k % 6));
    SceneMirror mirror(config);
    mirror.update(reach.robot_state());
    RobotScene own;
    add_task_bodies(own, reach.task());
    update_poses(own, reach.task().world());
    REQUIRE(own.scene.items.size() == mirror.scene().items.size());
    for (size_t i = 0; i < own.scene.items.size(); ++i)
      CHECK(own.scene.items[i].pose.matrix().isApprox(mirror.scene().items[i].pose.matrix(), 1e-4f));
  }
  // A manipulation task: the copy draws the cubes and goal markers where the env has them.
  const EnvConfig stack = default_env_config("stack");
  auto env = make_env(stack);
  env->reset(5);
  auto& m = dynamic_cast<ManipulationEnv&>(*env);
  ManipulationExpert expert(*env);
  expert.reset();
  for (int k = 0; k < 20; ++k) env->step(expert.act());  // the first cube is carried away
  SceneMirror mirror(stack);
  mirror.update(m.robot_state());
  RobotScene own;
  add_task_bodies(own, m.world());
  update_poses(own, m.world().world());
  REQUIRE(own.scene.items.size() == mirror.scene().items.size());
  for (size_t i = 0; i < own.scene.items.size(); ++i)
    CHECK(own.scene.items[i].pose.matrix().isApprox(mirror.scene().items[i].pose.matrix(), 1e-4f));
  CHECK_THROWS_WITH(SceneMirror(default_env_config("cartpole")), Contains("env cartpole has no robot scene"));
}

TEST_CASE("the status shows the real distance to the target before the first step", "[teleop]") {
  for (const char* name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    INFO(name);
    EnvConfig c = default_env_config(name);
    c.get<ReachOptions>().random_target = true;
    auto env = make_env(c);
    TeleopSession session(*env, 3, nullptr, to_json(c));
    const RobotSnapshot start = session.control().robot_state();
    const float expected = (start.effector_position - start.target).norm();
    CHECK(expected > 0.05f);  // the robot starts away from its target
    CHECK(session.status().info.distance == Approx(expected));
    CHECK(session.status().steps == 0);
    // The first step's distance is the env's own, a small move from the start's.
    session.act(move_action(Move::PlusZ, env->spec().action));
    CHECK(std::abs(session.status().info.distance - expected) < 0.1f);
    session.reset();
    CHECK(session.status().info.distance > 0.05f);
  }
}

TEST_CASE("the scene mirror marks the target tomato among the tree's tomatoes, and only it", "[teleop]") {
  EnvConfig config = default_env_config("inmoov_tomato");
  config.get<ReachOptions>().random_target = true;
  auto env = make_env(config);
  auto& reach = dynamic_cast<ReachEnv&>(*env);
  SceneMirror mirror(config);
  std::set<int> marked;
  for (std::uint64_t seed = 0; seed < 12; ++seed) {
    env->reset(seed);
    const RobotSnapshot state = reach.robot_state();
    mirror.update(state);
    const int item = mirror.target_item();
    REQUIRE(item >= 0);
    marked.insert(item);
    CHECK((mirror.scene().items[static_cast<size_t>(item)].pose.translation() - state.target).norm() < 0.01f);
    int yellow = 0;
    for (const auto& it : mirror.scene().items) yellow += it.rgba.isApprox(SceneMirror::target_colour());
    CHECK(yellow == 1);  // the previous target took its own colour back
  }
  CHECK(marked.size() > 2);  // random targets: the mark moved from tomato to tomato

  SceneMirror button(default_env_config("jaka_button"));
  auto button_env = make_env(default_env_config("jaka_button"));
  button_env->reset(0);
  button.update(dynamic_cast<ReachEnv&>(*button_env).robot_state());
  CHECK(button.target_item() == -1);  // one button: nothing to tell apart
}
