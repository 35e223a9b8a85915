// RobotControl (core/robot_control.hpp) as the reaching envs implement it: what a teleoperation
// window and the remote `position` / `joints` / `cameras` / `state` requests rely on.
#include <catch2/catch.hpp>

#include <cmath>

#include "env_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;
using rdsim::test::env_config;

namespace {

RobotControl& control(Env& env) {
  auto* c = dynamic_cast<RobotControl*>(&env);
  REQUIRE(c != nullptr);
  return *c;
}

int joint_index(const RobotInfo& info, const std::string& name) {
  for (size_t i = 0; i < info.joints.size(); ++i)
    if (info.joints[i].name == name) return static_cast<int>(i);
  FAIL("no joint " << name);
  return -1;
}

// Mean absolute difference of two images (0..255).
double image_difference(const Image& a, const Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) sum += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  return sum / static_cast<double>(a.rgb.size());
}

}  // namespace

TEST_CASE("robot control: every reaching env offers it, cartpole does not", "[envs][robot_control]") {
  for (const char* name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    INFO(name);
    auto env = make_env(env_config(name));
    const RobotInfo& info = control(*env).robot_info();
    CHECK_FALSE(info.joints.empty());
    CHECK_FALSE(info.cameras.empty());
    env->reset(1);
    CHECK(info.workspace.contains(control(*env).robot_state().effector_position));
    for (const JointInfo& j : info.joints) CHECK(j.lower <= j.upper);
  }
  auto cartpole = make_env(env_config("cartpole"));
  CHECK(dynamic_cast<RobotControl*>(cartpole.get()) == nullptr);
}

TEST_CASE("robot control: the Jaka's joints, limits and wrist camera as its URDF says", "[envs][robot_control]") {
  auto env = make_env(env_config("jaka_button"));
  const RobotInfo& info = control(*env).robot_info();
  CHECK(info.effector_link == "flange_link");
  REQUIRE(info.joints.size() == 6);
  CHECK(info.joints[0].name == "joint_1");
  CHECK(info.joints[1].lower == Approx(-1.4835299f));
  CHECK(info.joints[1].upper == Approx(4.6251225f));
  CHECK(info.joints[0].max_velocity == Approx(3.1416f));
  REQUIRE(info.cameras.size() == 2);
  CHECK(info.cameras[0].name == "wrist");
  CHECK(info.cameras[0].link == "flange_link");
  CHECK(info.cameras[1].name == "scene");
  CHECK(info.cameras[1].link.empty());
}

TEST_CASE("robot control: move_effector brings the flange to an absolute point by IK, one env step per call",
          "[envs][robot_control]") {
  auto env = make_env(env_config("jaka_button"));
  RobotControl& c = control(*env);
  env->reset(7);
  const Eigen::Vector3f goal(0.40f, 0.15f, 0.12f);
  StepResult r;
  int calls = 0;
  for (; calls < 150; ++calls) {
    r = c.move_effector(goal);
    if (r.terminated || r.truncated) break;
    if ((c.robot_state().effector_position - goal).norm() < 0.002f) break;
  }
  const RobotSnapshot s = c.robot_state();
  CHECK((s.effector_position - goal).norm() < 0.002f);
  CHECK(s.steps == calls + 1);  // each call is one env step
  // Judged like a step: reward = -distance to the button.
  CHECK(r.reward == Approx(-(s.effector_position - s.target).norm()).margin(1e-5));
  CHECK(r.info.distance == Approx((s.effector_position - s.target).norm()).margin(1e-5));
  // The IK keeps the joints within their limits.
  const RobotInfo& info = c.robot_info();
  for (size_t i = 0; i < info.joints.size(); ++i) {
    CHECK(s.joint_targets[static_cast<Eigen::Index>(i)] >= info.joints[i].lower);
    CHECK(s.joint_targets[static_cast<Eigen::Index>(i)] <= info.joints[i].upper);
  }
}

TEST_CASE("robot control: a point outside the workspace is clipped into it, reaching the button is a success",
          "[envs][robot_control]") {
  auto env = make_env(env_config("jaka_button"));
  RobotControl& c = control(*env);
  env->reset(3);
  const Eigen::Vector3f button = c.robot_state().target;
  StepResult r;
  for (int i = 0; i < 200 && !r.terminated; ++i) r = c.move_effector(button);
  CHECK(r.terminated);
  CHECK(r.info.success);
  // After the episode ended, control calls move nothing (like Env::step) until reset.
  const RobotSnapshot before = c.robot_state();
  r = c.move_effector(Eigen::Vector3f(0.3f, 0.3f, 0.4f));
  CHECK(r.terminated);
  CHECK(r.reward == 0.0f);
  CHECK(c.robot_state().joint_positions == before.joint_positions);
  // Far outside the box: the target is clipped, so the flange heads for the box's corner.
  env->reset(3);
  for (int i = 0; i < 5; ++i) c.move_effector(Eigen::Vector3f(5.0f, 0.0f, 0.3f));
  CHECK(c.robot_state().effector_position.x() <= c.robot_info().workspace.max().x() + 0.03f);
}

TEST_CASE("robot control: joint targets are clamped to the limits and move the joints", "[envs][robot_control]") {
  auto env = make_env(env_config("inmoov_tomato"));
  RobotControl& c = control(*env);
  env->reset(1);
  const RobotInfo& info = c.robot_info();
  CHECK(info.joints.size() == 54);
  const int pitch = joint_index(info, "neck_pitch");
  Eigen::VectorXf q = c.robot_state().joint_targets;
  q[pitch] = 5.0f;  // beyond its upper limit (0.785 rad); 2 rad/s: 0.4 s to get there
  for (int i = 0; i < 150; ++i) c.set_joint_targets(q);
  const RobotSnapshot s = c.robot_state();
  CHECK(s.joint_targets[pitch] == Approx(info.joints[static_cast<size_t>(pitch)].upper));
  CHECK(s.joint_positions[pitch] == Approx(info.joints[static_cast<size_t>(pitch)].upper).margin(0.02));
  CHECK(s.steps == 150);
  CHECK_THROWS_WITH(c.set_joint_targets(Eigen::VectorXf::Zero(3)), Contains("expected 54 joint targets"));
  Eigen::VectorXf bad = q;
  bad[0] = std::nanf("");
  CHECK_THROWS_WITH(c.set_joint_targets(bad), Contains("finite"));
  CHECK_THROWS_WITH(c.move_effector(Eigen::Vector3f(0, INFINITY, 0)), Contains("finite"));
}

TEST_CASE("robot control: first-person cameras draw at the asked size and follow the robot", "[envs][robot_control]") {
  auto env = make_env(env_config("inmoov_tomato"));
  RobotControl& c = control(*env);
  env->reset(1);
  const RobotInfo& info = c.robot_info();
  REQUIRE(info.cameras.size() == 3);
  CHECK(info.cameras[0].name == "left_eye");
  CHECK(info.cameras[1].name == "right_eye");
  CHECK(info.cameras[2].name == "scene");
  Image left, right, small;
  c.camera_image(0, 96, 64, left);
  CHECK(left.width == 96);
  CHECK(left.height == 64);
  CHECK(left.rgb.size() == 96u * 64u * 3u);
  c.camera_image(1, 96, 64, right);
  CHECK(image_difference(left, right) > 0.1);  // 6.6 cm apart: not the same picture
  c.camera_image(0, 32, 32, small);            // another size: a new renderer
  CHECK(small.rgb.size() == 32u * 32u * 3u);
  // Turning the head changes what the eyes see.
  Eigen::VectorXf q = c.robot_state().joint_targets;
  q[joint_index(info, "neck_pitch")] = 0.6f;
  for (int i = 0; i < 60; ++i) c.set_joint_targets(q);
  Image down;
  c.camera_image(0, 96, 64, down);
  CHECK(image_difference(left, down) > 5.0);
  CHECK_THROWS_WITH(c.camera_image(3, 64, 64, down), Contains("no such camera"));
  CHECK_THROWS_WITH(c.camera_image(0, 0, 64, down), Contains("1..4096"));
  CHECK_THROWS_WITH(c.camera_image(0, 64, 5000, down), Contains("1..4096"));
}

TEST_CASE("robot control: the scene camera is the raw-pixel observation's camera", "[envs][robot_control]") {
  EnvConfig config = env_config("jaka_obstacle", true);
  config.observation = ObservationMode::RawPixels;
  auto env = make_env(config);
  const Observation o = env->reset(2);
  Image scene;
  control(*env).camera_image(1, config.image_width, config.image_height, scene);
  CHECK(scene.rgb == o.pixels);
}

TEST_CASE("robot control: the same calls from the same seed give bit-identical states", "[envs][robot_control]") {
  auto run = [] {
    auto env = make_env(env_config("jaka_obstacle", true));
    RobotControl& c = control(*env);
    env->reset(11);
    std::vector<float> trace;
    for (int i = 0; i < 30; ++i) {
      const StepResult r = i % 3 ? c.move_effector(Eigen::Vector3f(0.5f, -0.1f, 0.2f)) : env->step(Action::discrete(i % 6));
      trace.push_back(r.reward);
      const RobotSnapshot s = c.robot_state();
      trace.insert(trace.end(), s.joint_positions.data(), s.joint_positions.data() + s.joint_positions.size());
    }
    return trace;
  };
  CHECK(run() == run());
}

namespace {

// Share of the image's pixels for which `is` holds (RGB bytes).
template <typename Predicate>
double share(const Image& image, Predicate is) {
  int n = 0;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) n += is(image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]);
  return static_cast<double>(n) / (image.width * image.height);
}

}  // namespace

TEST_CASE("robot control: the Jaka's wrist camera at home sees the task, not only the table under it", "[envs][robot_control]") {
  // jaka_obstacle's home: the column ahead (orange: red well above green, no blue); before the
  // camera was tilted off the tool axis this was a plain square of table.
  auto obstacle = make_env(env_config("jaka_obstacle"));
  obstacle->reset(0);
  Image image;
  control(*obstacle).camera_image(0, 160, 120, image);
  const auto orange = [](int r, int g, int b) { return r > 2 * g && b < 30 && r > 40; };
  CHECK(share(image, orange) > 0.05);
  // jaka_button's home: the red button under the flange is still in view.
  auto button = make_env(env_config("jaka_button"));
  button->reset(0);
  control(*button).camera_image(0, 160, 120, image);
  const auto red = [](int r, int g, int b) { return r > 120 && g < 60 && b < 60; };
  CHECK(share(image, red) > 0.008);
}
