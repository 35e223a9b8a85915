// The reaching envs' options that reproduce RobotDrlSim's task semantics (configs/paper/), each on
// its own against the default it replaces, and the presets' own numbers reaching the simulation.
#include <catch2/catch.hpp>
#include <algorithm>
#include <vector>

#include "env_test_util.hpp"
#include "rdsim/envs/reaching/jaka_obstacle.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;
using namespace rdsim::test;

namespace {

ReachEnv& reach(Env& env) { return dynamic_cast<ReachEnv&>(env); }

Eigen::Vector3f column_position(const ReachEnv& env) {
  return env.task().world().static_pose(env.task().static_body(JakaObstacle::column_index)).translation();
}

}  // namespace

TEST_CASE("observation_layout relative: end effector - target, then end effector - each landmark", "[envs][paper]") {
  EnvConfig c = env_config("jaka_button", true);
  c.get<ReachOptions>().observation_layout = ObservationLayout::Relative;
  auto env = make_env(c);
  CHECK(env->spec().observation.shape == std::vector<int>{3});
  Observation o = env->reset(1);
  const ReachTask& task = reach(*env).task();
  CHECK((o.values - (task.ee_position() - task.target())).norm() < 1e-6f);
  o = env->step(Action::discrete(5)).observation;
  CHECK((o.values - (task.ee_position() - task.target())).norm() < 1e-6f);

  EnvConfig oc = env_config("jaka_obstacle");
  oc.get<ReachOptions>().observation_layout = ObservationLayout::Relative;
  auto obstacle = make_env(oc);
  CHECK(obstacle->spec().observation.shape == std::vector<int>{6});
  o = obstacle->reset(2);
  const ReachTask& t = reach(*obstacle).task();
  CHECK((o.values.head<3>() - (t.ee_position() - t.target())).norm() < 1e-6f);
  CHECK((o.values.tail<3>() - (t.ee_position() - column_position(reach(*obstacle)))).norm() < 1e-6f);
}

TEST_CASE("end_on_success false: success does not end an episode, info.success is its last step's", "[envs][paper]") {
  EnvConfig c = env_config("jaka_button");
  c.get<ReachOptions>().success_threshold = 10.0;  // every step is within the threshold
  c.max_steps = 5;
  auto ends = make_env(c);
  ends->reset(1);
  StepResult r = ends->step(Action::discrete(0));
  CHECK(r.terminated);
  CHECK(r.info.success);

  c.get<ReachOptions>().end_on_success = false;
  auto goes_on = make_env(c);
  goes_on->reset(1);
  for (int t = 1; t <= 5; ++t) {
    INFO("step " << t);
    r = goes_on->step(Action::discrete(t % 2));
    CHECK_FALSE(r.terminated);
    CHECK(r.truncated == (t == 5));
    CHECK(r.info.success == (t == 5));
  }
}

TEST_CASE("workspace_bounds false: nothing is out of bounds, goals are not clipped", "[envs][paper]") {
  EnvConfig c = env_config("jaka_button");
  c.get<ReachOptions>().max_distance = 0.001;  // farther than 1 mm from the button ends a bounded episode at once
  auto bounded = make_env(c);
  bounded->reset(1);
  StepResult r = bounded->step(Action::discrete(1));
  CHECK(r.terminated);
  CHECK(r.info.out_of_bounds);

  c.get<ReachOptions>().workspace_bounds = false;
  c.get<ReachOptions>().action_step = 1.0;  // goals 1 m away, far outside the workspace box
  c.max_steps = 60;
  auto free = make_env(c);
  free->reset(1);
  for (int t = 0; t < 60; ++t) {
    r = free->step(Action::discrete(5));  // +z
    CHECK_FALSE(r.info.out_of_bounds);
    CHECK_FALSE(r.terminated);
  }
  // Unclipped goals lift the flange past the box's top (z = 0.55 m) and its 3 cm margin; a clipped
  // goal stops at the top (the arm reaches about 0.65 m there).
  CHECK(reach(*free).task().ee_position().z() > 0.55f + 0.03f);
}

TEST_CASE("reset_pose rest and reset_noise 0: every episode starts at RobotDrlSim's pose", "[envs][paper]") {
  for (const char* name : {"jaka_button", "inmoov_tomato"}) {
    INFO(name);
    EnvConfig c = env_config(name, true);
    c.get<ReachOptions>().reset_pose = ResetPose::Rest;
    c.get<ReachOptions>().reset_noise = 0.0;
    auto env = make_env(c);
    const ReachTask& task = reach(*env).task();
    Eigen::VectorXf rest = Eigen::VectorXf::Zero(task.robot().dof());
    if (std::string(name) == "jaka_button") rest << 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f;
    for (std::uint64_t seed = 0; seed < 3; ++seed) {
      env->reset(seed);
      CHECK(task.robot().joint_positions() == rest);
    }
  }
  // The defaults: home plus seeded noise.
  auto env = make_env(env_config("jaka_button"));
  env->reset(0);
  const Eigen::VectorXf a = reach(*env).task().robot().joint_positions();
  env->reset(1);
  CHECK(reach(*env).task().robot().joint_positions() != a);
  CHECK((a - reach(*env).task().spec().home).cwiseAbs().maxCoeff() <= 0.02f + 1e-6f);
}

TEST_CASE("ik_joints all: the InMoov's IK also moves the torso joints on the way to the palm", "[envs][paper]") {
  EnvConfig c = env_config("inmoov_tomato");
  CHECK(reach(*make_env(c)).task().chain().dof() == 6);
  c.get<ReachOptions>().ik_joints = IkJoints::All;
  CHECK(reach(*make_env(c)).task().chain().dof() == 8);  // + mid_stomach, top_stomach
}

TEST_CASE("paper presets: their physics numbers reach the world, the robot and the IK", "[envs][paper]") {
  for (const char* name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    for (bool pixels : {false, true}) {
      INFO(name << (pixels ? " pixels" : ""));
      const EnvConfig c = paper_env_config(name, pixels);
      auto env = make_env(c);
      const ReachTask& task = reach(*env).task();
      CHECK(task.world().settings().solver_iterations == 150);
      CHECK(task.world().settings().time_step == 1.0 / 240.0);
      CHECK(env->spec().control_dt == Approx(2.0 / 240.0));
      CHECK(task.spec().action_repeat == 2);
      CHECK(task.spec().ik_method == IkMethod::NullSpace);
      CHECK(task.spec().ik_iterations == 20);
      CHECK(task.spec().robot.drive == JointDrive::ConstraintMotor);
      CHECK(task.spec().robot.limit_constraints);
      CHECK(task.spec().robot.position_gain == 0.1f);
      CHECK(task.spec().robot.velocity_gain == 1.0f);
      // pybullet's setJointMotorControlArray (no speed limit), link damping and solver defaults.
      CHECK_FALSE(task.spec().robot.motor_speed_limits);
      CHECK(task.spec().robot.link_damping == 0.04f);
      CHECK(task.world().settings().contact_erp == 0.08);
      // pybullet warm-starts contacts from a tenth of their last impulse, the presets from all of it;
      // pybullet stops at a squared residual of 1e-7, the presets iterate on to 1e-9 (the speed-ups
      // and their tolerance: docs/benchmarks.md).
      CHECK(task.world().settings().warmstarting_factor == 1.0);
      CHECK(task.world().settings().solver_residual_threshold == 1e-9);
      CHECK(task.spec().move_noise == 0.0f);
      CHECK(task.spec().step == (std::string(name) == "inmoov_tomato" ? 1.2f : 1.0f));
      CHECK(env->spec().max_episode_steps == (std::string(name) == "jaka_obstacle" ? 250 : 1000));
      if (pixels) CHECK(env->spec().observation.shape == std::vector<int>{224, 224, 3});
      else CHECK(env->spec().observation.shape == std::vector<int>{std::string(name) == "jaka_obstacle" ? 6 : 3});
    }
  }
}

TEST_CASE("paper presets: a far-target move carries the end effector along its axis", "[envs][paper]") {
  // RobotDrlSim's moves aim 1 m (InMoov 1.2 m) away: the IK solution is far from the current joints,
  // the position motors (kp 0.1) approach it a little each step, and the joint limits and the pull
  // towards the rest pose bend the path, so the effector drifts sideways too. What must hold: from
  // the rest pose each of the six moves, repeated, goes its own way along its axis, and no step jumps.
  for (const char* name : {"jaka_button", "inmoov_tomato"}) {
    auto env = make_env(paper_env_config(name));
    const ReachTask& task = reach(*env).task();
    for (int action = 0; action < 6; ++action) {
      const int axis = action / 2;
      const float sign = action % 2 ? 1.0f : -1.0f;  // Discrete(6): -x, +x, -y, +y, -z, +z
      env->reset(1);
      const Eigen::Vector3f before = task.ee_position();
      float largest_step = 0.0f;
      for (int t = 0; t < 30; ++t) {
        const Eigen::Vector3f p = task.ee_position();
        env->step(Action::discrete(action));
        largest_step = std::max(largest_step, (task.ee_position() - p).norm());
      }
      const Eigen::Vector3f moved = task.ee_position() - before;
      INFO(name << " action " << action << " moved " << moved.transpose());
      // The InMoov's arm hangs straight down at its rest pose: -z is blocked, and the IK swings the
      // hand up and sideways instead (pybullet's own IK and motors do the same, within 0.1 mm:
      // tools/fidelity).
      const bool blocked = std::string(name) == "inmoov_tomato" && action == 4;
      if (blocked)
        CHECK(moved.norm() > 0.04f);
      else
        CHECK(sign * moved[axis] > 0.04f);  // 4 cm or more its way in 30 steps (1/4 s)
      CHECK(largest_step < 0.1f);          // the motors' URDF efforts bound one step (2/240 s)
    }
  }
}

TEST_CASE("column_motion random_walk: the column wanders within 5 cm by the seed and is back at reset", "[envs][paper]") {
  EnvConfig c = env_config("jaka_obstacle");
  c.get<ObstacleOptions>().column_motion = ColumnMotion::RandomWalk;
  c.max_steps = 150;
  c.get<ReachOptions>().max_distance = 5.0;
  auto path = [&](std::uint64_t seed) {
    auto env = make_env(c);
    env->reset(seed);
    std::vector<Eigen::Vector3f> out;
    for (int t = 0; t < 100; ++t) {
      const StepResult r = env->step(Action::discrete(t % 2 ? 4 : 5));  // up and down beside the column
      const Eigen::Vector3f column = column_position(reach(*env));
      out.push_back(column);
      // The observation measures from where the column is now (full layout: values 3..5).
      CHECK((r.observation.values.segment<3>(3) - (reach(*env).task().ee_position() - column)).norm() < 1e-5f);
    }
    env->reset();
    CHECK((column_position(reach(*env)) - Eigen::Vector3f(0.35f, 0.15f, 0.0f)).norm() < 1e-6f);
    return out;
  };
  const std::vector<Eigen::Vector3f> a = path(4);
  float farthest = 0.0f;
  for (const Eigen::Vector3f& p : a) {
    const Eigen::Vector3f offset = p - Eigen::Vector3f(0.35f, 0.15f, 0.0f);
    CHECK(offset.head<2>().cwiseAbs().maxCoeff() <= 0.05f + 1e-6f);
    CHECK(std::abs(offset.z()) < 1e-6f);
    farthest = std::max(farthest, offset.norm());
  }
  CHECK(farthest > 0.005f);
  CHECK(a == path(4));
  CHECK(a != path(5));
}

TEST_CASE("reward inverse_distance: 1/d - 2t/T, -10 per step on the column without ending, +10 within 0.1 m", "[envs][paper]") {
  EnvConfig c = env_config("jaka_obstacle");
  c.get<ObstacleOptions>().reward = RewardRule::InverseDistance;
  c.max_steps = 250;
  auto env = make_env(c);
  Observation o = env->reset(0);
  bool touched = false;
  for (int t = 1; t <= 250; ++t) {
    // Straight at the button: through the column (tests/envs/test_jaka_obstacle.cpp).
    const StepResult r = env->step(greedy_action(to_target(o)));
    o = r.observation;
    const float d = r.info.distance;
    float expected = 1.0f / std::max(d, 0.01f) - 2.0f * static_cast<float>(t) / 250.0f;
    if (r.info.collision) expected -= 10.0f;
    if (d < 0.1f) expected += 10.0f;
    if (r.info.out_of_bounds) expected -= 0.9f * static_cast<float>(250 - t);
    INFO("step " << t << " d " << d);
    CHECK(r.reward == Approx(expected).epsilon(1e-6));
    touched = touched || r.info.collision;
    if (r.info.collision) CHECK_FALSE(r.terminated);
    if (r.terminated || r.truncated) break;
  }
  CHECK(touched);
}
