#include <catch2/catch.hpp>

#include <Eigen/Cholesky>

#include "rdsim/core/rng.hpp"
#include "rdsim/sim/joint_dynamics.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/urdf_loader.hpp"
#include "sim_test_assets.hpp"

using namespace rdsim;

namespace {

Eigen::VectorXd random_vector(Rng& rng, int n, double span) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = rng.uniform(-span, span);
  return v;
}

}  // namespace

TEST_CASE("Mass matrix and bias agree with inverse dynamics", "[dynamics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  JointDynamics dyn(m);
  REQUIRE(dyn.dof() == 6);
  const Eigen::Vector3d g(0, 0, -9.8);
  Rng rng(9);
  for (int t = 0; t < 20; ++t) {
    const Eigen::VectorXd q = random_vector(rng, 6, 3.0), qd = random_vector(rng, 6, 2.0), qdd = random_vector(rng, 6, 5.0);
    Eigen::MatrixXd mass;
    Eigen::VectorXd bias, tau;
    dyn.mass_matrix_and_bias(q, qd, g, mass, bias);
    dyn.inverse_dynamics(q, qd, qdd, g, tau);
    CHECK((mass * qdd + bias - tau).cwiseAbs().maxCoeff() < 1e-9);
    CHECK((mass - mass.transpose()).cwiseAbs().maxCoeff() < 1e-12);
    CHECK(mass.llt().info() == Eigen::Success);  // positive definite
  }
}

TEST_CASE("Holding the stretched arm needs the hand-computed gravity torque", "[dynamics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  JointDynamics dyn(m);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  Eigen::VectorXd tau;
  dyn.inverse_dynamics(zero, zero, zero, Eigen::Vector3d(0, 0, -9.8), tau);
  // At q = 0 every centre of mass beyond joint_2 lies at height 0.12 and distance x from the
  // shoulder: upper arm 0.18, forearm 0.36 + 0.15175, the wrist parts at 0.6635.
  const double moment = 6.0 * 0.18 + 3.2 * (0.36 + 0.15175) + (1.6 + 1.6 + 0.6 + 0.15) * 0.6635;
  CHECK(tau[1] == Approx(9.8 * moment).epsilon(1e-9));                     // joint_2 (axis -y)
  const double forearm_moment = 3.2 * 0.15175 + (1.6 + 1.6 + 0.6 + 0.15) * 0.3035;
  CHECK(tau[2] == Approx(9.8 * forearm_moment).epsilon(1e-9));             // joint_3
  CHECK(tau[0] == Approx(0.0).margin(1e-9));                               // vertical axis
}

TEST_CASE("The computed-torque drive reaches exactly the asked speed in one Bullet step", "[dynamics][physics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  PhysicsWorld world;  // gravity on
  Robot& robot = world.add_robot(m, Eigen::Isometry3f::Identity());
  Eigen::VectorXf q(6);
  q << 0.3f, 1.0f, -1.6f, 0.5f, 1.0f, 0.2f;
  robot.reset_joints(q);
  Eigen::VectorXf target = q;
  target[2] += 0.002f;  // small enough for every joint to stay below its effort limit
  target[5] -= 0.001f;
  robot.set_position_targets(target);
  world.step();
  const double dt = world.settings().time_step;
  const Eigen::VectorXf v = robot.joint_velocities();
  // kp = kd = 1: v* = (target - q) / dt; all other joints must stay at rest despite gravity.
  CHECK(v[2] == Approx(0.002 / dt).epsilon(1e-3));
  CHECK(v[5] == Approx(-0.001 / dt).epsilon(1e-3));
  for (int i : {0, 1, 3, 4}) CHECK(std::abs(v[i]) < 1e-3f);
}

TEST_CASE("Branched trees: joints on different branches do not couple", "[dynamics]") {
  // A torso with two two-joint arms.
  auto link = [](const std::string& name) {
    return "<link name=\"" + name + "\"><inertial><origin xyz=\"0.1 0.02 0\"/><mass value=\"1.5\"/><inertia ixx=\"0.01\" "
           "ixy=\"0.001\" ixz=\"0\" iyy=\"0.02\" iyz=\"0\" izz=\"0.015\"/></inertial></link>";
  };
  auto joint = [](const std::string& name, const std::string& parent, const std::string& child, const std::string& xyz,
                  const std::string& axis) {
    return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + child +
           "\"/><origin xyz=\"" + xyz + "\" rpy=\"0.1 0.2 0.3\"/><axis xyz=\"" + axis +
           "\"/><limit lower=\"-3\" upper=\"3\" effort=\"50\" velocity=\"2\"/></joint>";
  };
  const std::string xml = "<robot name=\"tree\">" + link("torso") + link("l1") + link("l2") + link("r1") + link("r2") +
                          joint("l_a", "torso", "l1", "0 0.2 0.5", "0 1 0") + joint("l_b", "l1", "l2", "0.3 0 0", "1 0 0") +
                          joint("r_a", "torso", "r1", "0 -0.2 0.5", "0 0 1") + joint("r_b", "r1", "r2", "0.3 0 0", "0 1 1") +
                          "</robot>";
  const RobotModel m = parse_urdf(xml, "tree.urdf");
  JointDynamics dyn(m);
  REQUIRE(dyn.dof() == 4);
  Rng rng(4);
  const Eigen::VectorXd q = random_vector(rng, 4, 2.0), qd = random_vector(rng, 4, 2.0), qdd = random_vector(rng, 4, 3.0);
  Eigen::MatrixXd mass;
  Eigen::VectorXd bias, tau;
  dyn.mass_matrix_and_bias(q, qd, Eigen::Vector3d(0, 0, -9.8), mass, bias);
  dyn.inverse_dynamics(q, qd, qdd, Eigen::Vector3d(0, 0, -9.8), tau);
  CHECK((mass * qdd + bias - tau).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(mass(0, 2) == 0.0);  // left and right arm joints
  CHECK(mass(1, 3) == 0.0);
  CHECK(mass(0, 1) != 0.0);
  CHECK(mass.llt().info() == Eigen::Success);
}
