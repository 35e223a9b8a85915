#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/ik.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/urdf_loader.hpp"
#include "sim_test_assets.hpp"

using namespace rdsim;

namespace {

Eigen::Isometry3f at(float x, float y, float z) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translation() << x, y, z;
  return t;
}

Eigen::VectorXf home() {
  Eigen::VectorXf q(6);
  q << 0.0f, 1.0f, -1.8f, 0.8f, 1.5708f, 0.0f;
  return q;
}

struct Scene {
  RobotModel jaka = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  PhysicsWorld world;
  int table;
  Robot* robot;
  explicit Scene(JointDrive drive = JointDrive::ComputedTorque, WorldSettings settings = {}) : world(settings) {
    // Table top at z = 0.75, robot standing on it.
    table = world.add_static_body(load_urdf(test_asset("objects/table.urdf")), at(0.35f, 0.0f, 0.75f));
    RobotOptions options;
    options.drive = drive;
    robot = &world.add_robot(jaka, at(0, 0, 0.75f), options);
    robot->reset_joints(home());
  }
};


// Every 50 steps, moves the targets that press the arm down onto the table and, after a few
// rounds, the base joint past its limit (contact and limit rows for the solver tests).
void press_onto_table(Scene& s, Eigen::VectorXf& target, int step) {
  if (step % 50 != 0) return;
  target[0] += 1.0f;
  target[1] -= 0.2f;
  target[3] += 0.15f;
  s.robot->set_position_targets(target);
}

// rdsim's gripper: the JAKA with its fingers on Bullet motors, coupled by a gear, squeezing a free
// cube between its pads while the arm lifts and swings it; the two fingers asked for different
// openings, so the coupling works against a motor all along. Returns the joints' and the cube's
// trace.
std::vector<float> grip_trace(const WorldSettings& settings) {
  PhysicsWorld world(settings);
  RobotModel model = load_urdf(test_asset("jaka/jaka_zu7_gripper.urdf"));
  RobotOptions options;
  options.drive = JointDrive::ComputedTorque;
  options.motor_dofs = {6, 7};  // finger_left_joint, finger_right_joint after the arm's 6
  options.coupled_dofs = {{6, 7}};
  Robot* robot = &world.add_robot(model, at(0, 0, 0), options);
  REQUIRE(robot->dof_of_joint(model.joint_index("finger_left_joint")) == 6);
  REQUIRE(robot->dof_of_joint(model.joint_index("finger_right_joint")) == 7);
  Eigen::VectorXf q = Eigen::VectorXf::Zero(robot->dof());
  q.head(6) << 0.0f, 1.0f, -1.8f, 0.8f, 1.5708f, 0.0f;
  q[options.motor_dofs[0]] = q[options.motor_dofs[1]] = 0.0425f;  // open
  robot->reset_joints(q);
  const Eigen::Vector3f tcp = robot->link_pose(model.require_link("gripper_tcp")).translation();
  const int cube = world.add_free_body(load_urdf(test_asset("objects/cube_blue.urdf")), at(tcp.x(), tcp.y(), tcp.z()));
  std::vector<float> trace;
  for (int k = 0; k < 300; ++k) {
    if (k == 0) {  // squeeze: one finger asked to close, the other to stay a little open
      q[options.motor_dofs[0]] = 0.0f;
      q[options.motor_dofs[1]] = 0.01f;
    }
    if (k == 100) q[1] -= 0.3f;  // lift
    if (k == 200) q[0] += 0.5f;  // swing
    robot->set_position_targets(q);
    world.step();
    for (int i = 0; i < robot->dof(); ++i) trace.push_back(robot->joint_position(i));
    for (int i = 0; i < robot->dof(); ++i) trace.push_back(robot->joint_velocity(i));
    const FreeBodyState b = world.free_body_state(cube);
    trace.insert(trace.end(), std::begin(b.transform), std::end(b.transform));
  }
  CHECK(world.touching({robot->body(), model.link_index("finger_left")}, {cube, -1}));  // still held
  CHECK(world.touching({robot->body(), model.link_index("finger_right")}, {cube, -1}));
  return trace;
}

}  // namespace

TEST_CASE("Position control moves every joint to its target", "[physics]") {
  for (JointDrive drive : {JointDrive::ComputedTorque, JointDrive::ConstraintMotor}) {
    Scene s(drive);
    const Eigen::VectorXf target = home() + Eigen::VectorXf::Constant(6, 0.3f);
    s.robot->set_position_targets(target);
    for (int k = 0; k < 240; ++k) s.world.step();
    INFO("drive " << static_cast<int>(drive));
    CHECK((s.robot->joint_positions() - target).cwiseAbs().maxCoeff() < 1e-3f);
    CHECK(s.robot->joint_velocities().cwiseAbs().maxCoeff() < 1e-2f);
  }
}

TEST_CASE("Joints never exceed their velocity limit", "[physics]") {
  Scene s;
  Eigen::VectorXf target = home();
  target[0] += 1.5f;  // needs 0.48 s at 180 deg/s
  s.robot->set_position_targets(target);
  float fastest = 0.0f;
  int steps = 0;
  while (std::abs(s.robot->joint_position(0) - target[0]) > 1e-3f && steps < 480) {
    s.world.step();
    ++steps;
    fastest = std::max(fastest, std::abs(s.robot->joint_velocity(0)));
  }
  CHECK(fastest <= 3.1416f * 1.001f);
  CHECK(fastest > 3.0f);  // and it does run at the limit
  CHECK(steps * s.world.settings().time_step >= 1.5 / 3.1416);
}

TEST_CASE("The arm holds its pose against gravity", "[physics]") {
  Scene s;
  for (int k = 0; k < 240; ++k) s.world.step();
  CHECK((s.robot->joint_positions() - home()).cwiseAbs().maxCoeff() < 1e-4f);
}

TEST_CASE("A contact query sees the flange touching the table when driven into it", "[physics]") {
  for (JointDrive drive : {JointDrive::ComputedTorque, JointDrive::ConstraintMotor}) {
    Scene s(drive);
    const int flange = s.jaka.require_link("flange_link");
    const KinematicChain chain(s.jaka, "flange_link");
    const BodyLink tool{s.robot->body(), flange}, table{s.table, -1};
    // Start 10 cm above the table (robot frame z = 0.10), tool pointing down.
    Eigen::Isometry3d above = Eigen::Isometry3d::Identity();
    above.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    above.translation() << 0.45, 0.0, 0.10;
    const IkResult start = solve_ik(chain, above, home().cast<double>());
    REQUIRE(start.converged);
    s.robot->reset_joints(start.q.cast<float>());
    for (int k = 0; k < 10; ++k) s.world.step();
    CHECK_FALSE(s.world.touching(tool, table));
    CHECK(s.world.penetration(tool, table) == 0.0f);

    // Ask for 5 cm below the surface: the table must stop the flange.
    Eigen::Isometry3d below = above;
    below.translation().z() = -0.05;
    s.robot->set_position_targets(solve_ik(chain, below, start.q).q.cast<float>());
    for (int k = 0; k < 240; ++k) s.world.step();
    INFO("drive " << static_cast<int>(drive));
    CHECK(s.world.touching(tool, table));
    CHECK(s.world.touching(table, {s.robot->body(), -1}));  // either order, any link
    CHECK(s.world.penetration(tool, table) < 0.01f);
    CHECK(s.robot->link_pose(flange).translation().z() > 0.75f - 0.01f);
    bool listed = false;
    for (const Contact& c : s.world.contacts())
      listed |= (c.a.body == s.robot->body() && c.a.link == flange && c.b.body == s.table) ||
                (c.b.body == s.robot->body() && c.b.link == flange && c.a.body == s.table);
    CHECK(listed);
  }
}

TEST_CASE("Static bodies can be moved", "[physics]") {
  PhysicsWorld world;
  const int button = world.add_static_body(load_urdf(test_asset("objects/button.urdf")), at(0.5f, 0.0f, 0.75f));
  CHECK(world.static_pose(button).translation().isApprox(Eigen::Vector3f(0.5f, 0.0f, 0.75f)));
  world.set_static_pose(button, at(0.6f, 0.2f, 0.75f));
  CHECK(world.static_pose(button).translation().isApprox(Eigen::Vector3f(0.6f, 0.2f, 0.75f)));
  CHECK_THROWS_AS(world.robot(button), Error);
}

TEST_CASE("A free body rests on the floor, is pushed by the arm, and comes back at rest when moved", "[physics]") {
  PhysicsWorld world;
  world.add_static_body(load_urdf(test_asset("objects/floor.urdf")), at(0.0f, 0.0f, 0.0f));
  const int button = world.add_free_body(load_urdf(test_asset("objects/paper_button.urdf")), at(0.5f, 0.0f, 0.0f));
  for (int k = 0; k < 240; ++k) world.step();
  CHECK((world.static_pose(button).translation() - Eigen::Vector3f(0.5f, 0.0f, 0.0f)).norm() < 2e-3f);

  // A 5 kg block in the flange's way: the arm sweeping through it shoves it.
  RobotOptions options;
  options.link_damping = 0.04f;
  Robot& arm = world.add_robot(load_urdf(test_asset("jaka/jaka_zu7.urdf")), at(0.0f, 0.0f, 0.0f), options);
  Eigen::VectorXf q(6);
  q << -0.809f, 0.889f, -1.754f, 2.077f, 1.667f, 0.0f;  // the flange 3 cm high, 0.5 m out, beside the block
  arm.reset_joints(q);
  q[0] = 0.391f;  // sweep across it
  arm.set_position_targets(q);
  for (int k = 0; k < 480; ++k) world.step();
  const float moved = (world.static_pose(button).translation() - Eigen::Vector3f(0.5f, 0.0f, 0.0f)).norm();
  INFO("moved " << moved);
  CHECK(moved > 0.01f);

  world.set_static_pose(button, at(1.0f, 1.0f, 0.0f));
  world.step();
  CHECK((world.static_pose(button).translation() - Eigen::Vector3f(1.0f, 1.0f, 0.0f)).norm() < 1e-3f);
  CHECK_THROWS_WITH(world.add_free_body(load_urdf(test_asset("jaka/jaka_zu7.urdf")), at(0.0f, 0.0f, 0.0f)),
                    Catch::Contains("a free body must be one link"));
}

TEST_CASE("Same inputs give bit-identical simulations, also after a reset", "[physics]") {
  auto run = [](Scene& s) {
    Eigen::VectorXf target = home();
    std::vector<float> trace;
    for (int k = 0; k < 300; ++k) {
      if (k % 50 == 0) {
        target[1] -= 0.15f;  // pushes the arm down onto the table: contacts included
        target[3] += 0.1f;
        s.robot->set_position_targets(target);
      }
      s.world.step();
      for (int i = 0; i < 6; ++i) trace.push_back(s.robot->joint_position(i));
    }
    return trace;
  };
  Scene a, b;
  const std::vector<float> first = run(a);
  CHECK(first == run(b));
  a.robot->reset_joints(home());
  CHECK(first == run(a));  // after a different history
}

TEST_CASE("Sparse joint rows give Bullet's dense rows' simulation bit for bit", "[physics]") {
  // Position motors and joint-limit rows on every joint, the paper presets' 150 iterations, the
  // arm pushed down onto the table (contact rows) and past a joint limit (limit rows).
  auto run = [](bool sparse, double residual_threshold) {
    WorldSettings settings;
    settings.solver_iterations = 150;
    settings.sparse_joint_rows = sparse;
    settings.solver_residual_threshold = residual_threshold;
    Scene s(JointDrive::ConstraintMotor, settings);
    s.robot->set_gains(0.1f, 1.0f);
    Eigen::VectorXf target = home();
    std::vector<float> trace;
    for (int k = 0; k < 400; ++k) {
      press_onto_table(s, target, k);
      s.world.step();
      for (int i = 0; i < 6; ++i) trace.push_back(s.robot->joint_position(i));
      for (int i = 0; i < 6; ++i) trace.push_back(s.robot->joint_velocity(i));
    }
    CHECK(s.world.touching({s.robot->body(), -1}, {s.table, -1}));
    return trace;
  };
  for (double threshold : {0.0, 1e-7}) {
    INFO("residual threshold " << threshold);
    CHECK(run(true, threshold) == run(false, threshold));
  }
}

TEST_CASE("Skipping pairs that are provably apart gives Bullet's own simulation bit for bit", "[physics]") {
  // The paper presets' solver, an arm on position motors sweeping its flange through a free
  // block that rests on a floor box: pairs near, apart, touching and coming apart again.
  auto run = [](bool skip, long long& skipped) {
    WorldSettings settings = pybullet_solver({});
    settings.solver_iterations = 150;
    settings.skip_separated_pairs = skip;
    PhysicsWorld world(settings);
    world.add_static_body(load_urdf(test_asset("objects/floor.urdf")), at(0.0f, 0.0f, 0.0f));
    const int block = world.add_free_body(load_urdf(test_asset("objects/paper_button.urdf")), at(0.5f, 0.0f, 0.0f));
    RobotOptions options;
    options.drive = JointDrive::ConstraintMotor;
    Robot& arm = world.add_robot(load_urdf(test_asset("jaka/jaka_zu7.urdf")), at(0.0f, 0.0f, 0.0f), options);
    arm.set_gains(0.1f, 1.0f);
    Eigen::VectorXf q(6);
    q << -0.809f, 0.889f, -1.754f, 2.077f, 1.667f, 0.0f;  // the flange 3 cm high, beside the block
    arm.reset_joints(q);
    std::vector<float> trace;
    for (int k = 0; k < 720; ++k) {
      if (k % 240 == 0) {
        q[0] = k == 240 ? -0.809f : 0.391f;  // across the block, back, and across again
        arm.set_position_targets(q);
      }
      world.step();
      for (int i = 0; i < 6; ++i) trace.push_back(arm.joint_position(i));
      for (int i = 0; i < 6; ++i) trace.push_back(arm.joint_velocity(i));
      const FreeBodyState b = world.free_body_state(block);
      trace.insert(trace.end(), std::begin(b.transform), std::end(b.transform));
    }
    CHECK((world.static_pose(block).translation() - Eigen::Vector3f(0.5f, 0.0f, 0.0f)).norm() > 0.01f);  // pushed
    skipped = world.work().pairs_skipped;
    return trace;
  };
  long long with = 0, without = 0;
  CHECK(run(true, with) == run(false, without));
  CHECK(with > 100);  // it did skip
  CHECK(without == 0);
}

TEST_CASE("The joint rows' block solve lands where Bullet's iterations converge, in fewer iterations", "[physics]") {
  // Position motors and joint limits (the arm driven past the base joint's limit), 150
  // iterations with the presets' early exit; block-solved or not, the solver stops within its
  // tolerance of the same answer.
  auto run = [](bool block, long long& iterations) {
    WorldSettings settings = pybullet_solver({});
    settings.solver_iterations = 150;
    settings.solver_residual_threshold = 1e-9;
    settings.joint_row_warm_start = 1.0;
    settings.joint_block_solve = block;
    Scene s(JointDrive::ConstraintMotor, settings);
    s.robot->set_gains(0.1f, 1.0f);
    Eigen::VectorXf target = home();
    std::vector<float> trace;
    for (int k = 0; k < 400; ++k) {
      if (k % 50 == 0) {
        target[0] += 1.0f;  // past the base joint's limit after a few rounds
        target[2] += 0.2f;
        target[4] -= 0.3f;
        s.robot->set_position_targets(target);
      }
      s.world.step();
      for (int i = 0; i < 6; ++i) trace.push_back(s.robot->joint_position(i));
    }
    iterations = s.world.work().solver_iterations;
    return trace;
  };
  long long block_iterations = 0, iterations = 0;
  const std::vector<float> a = run(true, block_iterations), b = run(false, iterations);
  float largest = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  INFO("largest joint difference " << largest << " rad; iterations " << block_iterations << " vs " << iterations);
  CHECK(largest < 1e-3f);
  CHECK(2 * block_iterations < iterations);
}

TEST_CASE("Joint rows' responses from rdsim's mass matrix keep Bullet's simulation to its tolerance", "[physics]") {
  // The presets' solver (150 iterations at most, early exit, warm starts, block solve), position
  // motors and joint limits (the base joint driven past its limit), arm pushed onto the table:
  // the rows' responses from M(q)^-1 (double) instead of Bullet's single-precision passes.
  auto run = [](bool mass_matrix, double threshold = 1e-9) {
    WorldSettings settings = pybullet_solver({});
    settings.solver_iterations = 150;
    settings.solver_residual_threshold = threshold;
    settings.joint_row_warm_start = 1.0;
    settings.joint_block_solve = true;
    settings.mass_matrix_responses = mass_matrix;
    Scene s(JointDrive::ConstraintMotor, settings);
    s.robot->set_gains(0.1f, 1.0f);
    Eigen::VectorXf target = home();
    std::vector<float> trace;
    for (int k = 0; k < 400; ++k) {
      press_onto_table(s, target, k);
      s.world.step();
      for (int i = 0; i < 6; ++i) trace.push_back(s.robot->joint_position(i));
    }
    CHECK(s.world.touching({s.robot->body(), -1}, {s.table, -1}));
    return trace;
  };
  auto largest_difference = [](const std::vector<float>& x, const std::vector<float>& y) {
    float largest = 0.0f;
    for (size_t i = 0; i < x.size(); ++i) largest = std::max(largest, std::abs(x[i] - y[i]));
    return largest;
  };
  const std::vector<float> bullet = run(false);
  const float responses = largest_difference(run(true), bullet);
  const float tolerance = largest_difference(run(false, 1e-10), bullet);  // the solver's own spread
  INFO("largest joint difference " << responses << " rad; with a 10x tighter residual threshold " << tolerance);
  CHECK(responses > 0.0f);  // the responses did change (rounding)
  CHECK(responses < 0.1f * tolerance);  // a tenth of what the solver's own tolerance moves (0.04 rad here)
}

TEST_CASE("A gripper's finger motors and coupling: rdsim's rows give Bullet's bit for bit", "[physics][gripper]") {
  WorldSettings settings;
  settings.solver_iterations = 10;
  WorldSettings bullet = settings;
  bullet.sparse_joint_rows = false;  // Bullet's btMultiBodyJointMotor and btMultiBodyGearConstraint
  CHECK(grip_trace(settings) == grip_trace(bullet));
}

TEST_CASE("A gripper's rows with responses from the drive's mass matrix keep Bullet's simulation to rounding", "[physics][gripper]") {
  WorldSettings settings;
  settings.solver_iterations = 10;
  WorldSettings responses = settings;
  responses.mass_matrix_responses = true;
  const std::vector<float> a = grip_trace(settings), b = grip_trace(responses);
  REQUIRE(a.size() == b.size());
  float largest = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  INFO("largest difference " << largest << " (rad, m, rad/s, m/s)");
  CHECK(largest > 0.0f);   // the responses did change (rounding)
  CHECK(largest < 1e-3f);
}

TEST_CASE("Welded held joints stay at their targets and are freed by anything that moves them", "[physics]") {
  WorldSettings settings;
  settings.solver_iterations = 150;
  PhysicsWorld world(settings);
  world.add_static_body(load_urdf(test_asset("objects/table.urdf")), at(0.35f, 0.0f, 0.75f));
  RobotOptions options;
  options.drive = JointDrive::ConstraintMotor;
  options.weld_held_joints = true;
  Robot& robot = world.add_robot(load_urdf(test_asset("jaka/jaka_zu7.urdf")), at(0, 0, 0.75f), options);
  robot.reset_joints(home());
  robot.hold({3, 4, 5});  // the wrist
  CHECK(robot.welded_dofs() == 3);
  const Eigen::Isometry3f flange = robot.link_pose(robot.model().require_link("flange_link"));
  for (int k = 0; k < 100; ++k) world.step();
  CHECK(robot.joint_positions() == home());  // nothing moves: the motors hold the rest
  CHECK(robot.joint_velocities().isZero());
  CHECK(robot.link_pose(robot.model().require_link("flange_link")).isApprox(flange, 1e-4f));

  // A state round trip keeps the welds; a target elsewhere frees that joint, which then moves.
  const RobotState s = robot.state();
  robot.set_state(s, "test");
  CHECK(robot.welded_dofs() == 3);
  robot.set_position_target(5, 0.5f);
  CHECK(robot.welded_dofs() == 2);
  for (int k = 0; k < 240; ++k) world.step();
  CHECK(robot.joint_position(5) == Approx(0.5f).margin(0.01f));
  CHECK(robot.joint_positions().head<5>().isApprox(home().head<5>(), 1e-3f));

  // A reset welds the held joints again; driving the arm down to the table frees those that carry
  // the links coming near it, before the contact.
  robot.reset_joints(home());
  CHECK(robot.welded_dofs() == 3);
  Eigen::VectorXf down = home();
  down[1] -= 0.8f;
  robot.set_position_targets(down);
  CHECK(robot.welded_dofs() == 3);
  bool freed_before_touching = false;
  for (int k = 0; k < 480 && !world.touching({robot.body(), -1}, {0, -1}); ++k) {
    world.step();
    freed_before_touching |= robot.welded_dofs() < 3 && !world.touching({robot.body(), -1}, {0, -1});
  }
  CHECK(freed_before_touching);
  CHECK(world.touching({robot.body(), -1}, {0, -1}));
}

TEST_CASE("Without weld_held_joints, or with the computed-torque drive, hold() welds nothing", "[physics]") {
  for (bool weld : {false, true}) {
    PhysicsWorld world;
    RobotOptions options;
    options.drive = weld ? JointDrive::ComputedTorque : JointDrive::ConstraintMotor;
    options.weld_held_joints = weld;
    Robot& robot = world.add_robot(load_urdf(test_asset("jaka/jaka_zu7.urdf")), at(0, 0, 0), options);
    robot.reset_joints(home());
    robot.hold({0, 1, 2, 3, 4, 5});
    CHECK(robot.welded_dofs() == 0);
  }
}

TEST_CASE("A joint-row warm start outside [0, 1] is refused", "[physics]") {
  WorldSettings settings;
  settings.joint_row_warm_start = 1.5;
  CHECK_THROWS_AS(PhysicsWorld(settings), Error);
  settings.joint_row_warm_start = -0.1;
  CHECK_THROWS_AS(PhysicsWorld(settings), Error);
}
