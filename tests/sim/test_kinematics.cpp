#include <catch2/catch.hpp>

#include <cmath>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/sim/kinematics.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/urdf_loader.hpp"
#include "sim_test_assets.hpp"

using namespace rdsim;

namespace {

using M4 = Eigen::Matrix4d;

M4 trans(double x, double y, double z) {
  M4 m = M4::Identity();
  m(0, 3) = x;
  m(1, 3) = y;
  m(2, 3) = z;
  return m;
}
M4 rot_x(double a) {
  M4 m = M4::Identity();
  m(1, 1) = std::cos(a), m(1, 2) = -std::sin(a), m(2, 1) = std::sin(a), m(2, 2) = std::cos(a);
  return m;
}
M4 rot_y(double a) {
  M4 m = M4::Identity();
  m(0, 0) = std::cos(a), m(0, 2) = std::sin(a), m(2, 0) = -std::sin(a), m(2, 2) = std::cos(a);
  return m;
}
M4 rot_z(double a) {
  M4 m = M4::Identity();
  m(0, 0) = std::cos(a), m(0, 1) = -std::sin(a), m(1, 0) = std::sin(a), m(1, 1) = std::cos(a);
  return m;
}

// The flange pose written out by hand from the numbers in assets/jaka/jaka_zu7.urdf (joints 2-4
// turn about -y, so +q is a rotation about y by -q).
M4 jaka_flange_by_hand(const JointVector& q) {
  return trans(0, 0, 0.12) * rot_z(q[0]) *                 // joint_1
         rot_y(-q[1]) *                                    // joint_2
         trans(0.36, 0, 0) * rot_y(-q[2]) *                // joint_3
         trans(0.3035, 0, 0) * rot_y(-q[3]) *              // joint_4
         trans(0, 0.114, 0) * rot_z(q[4]) *                // joint_5
         trans(0, 0, -0.110) * rot_y(q[5]) *               // joint_6
         trans(0, 0.107, 0) * rot_x(-M_PI / 2);            // flange_fixed
}

JointVector random_config(const KinematicChain& chain, Rng& rng, double span = M_PI) {
  JointVector q(chain.dof());
  for (int i = 0; i < chain.dof(); ++i)
    q[i] = rng.uniform(std::max(chain.lower()[i], -span), std::min(chain.upper()[i], span));
  return q;
}

}  // namespace

TEST_CASE("Jaka forward kinematics matches hand-chained transforms", "[kinematics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  REQUIRE(chain.dof() == 6);
  Rng rng(7);
  for (int t = 0; t < 25; ++t) {
    const JointVector q = random_config(chain, rng);
    const M4 expected = jaka_flange_by_hand(q);
    CHECK((chain.forward(q).matrix() - expected).cwiseAbs().maxCoeff() < 1e-6);  // URDF's pi/2 has 8 digits
    const auto poses = link_poses(m, Eigen::VectorXd(q));
    CHECK((poses[7].matrix() - expected).cwiseAbs().maxCoeff() < 1e-6);
  }
  // Zero pose: stretched along +x, flange facing +y (documented in the URDF).
  const Eigen::Isometry3d zero = chain.forward(JointVector::Zero(6));
  CHECK(zero.translation().isApprox(Eigen::Vector3d(0.6635, 0.221, 0.01), 1e-9));
  CHECK(zero.linear().col(2).isApprox(Eigen::Vector3d(0, 1, 0), 1e-6));
}

TEST_CASE("The chain Jacobian matches finite differences", "[kinematics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  Rng rng(11);
  for (int t = 0; t < 10; ++t) {
    const JointVector q = random_config(chain, rng);
    ChainJacobian j;
    const Eigen::Isometry3d tip = chain.forward(q, j);
    const double h = 1e-6;
    for (int i = 0; i < 6; ++i) {
      JointVector qh = q;
      qh[i] += h;
      const Eigen::Isometry3d moved = chain.forward(qh);
      const Eigen::Vector3d dp = (moved.translation() - tip.translation()) / h;
      const Eigen::AngleAxisd dr(moved.linear() * tip.linear().transpose());
      CHECK((dp - j.col(i).head<3>()).norm() < 1e-5);
      CHECK((dr.angle() / h * dr.axis() - j.col(i).tail<3>()).norm() < 1e-5);
    }
  }
}

TEST_CASE("Bullet's link poses agree with our forward kinematics", "[kinematics][physics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const KinematicChain chain(m, "flange_link");
  PhysicsWorld world;
  Eigen::Isometry3f base = Eigen::Isometry3f::Identity();
  base.translation() << 0.2f, -0.1f, 0.75f;
  base.linear() = Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  Robot& robot = world.add_robot(m, base);
  Rng rng(3);
  for (int t = 0; t < 20; ++t) {
    const JointVector q = random_config(chain, rng);
    robot.reset_joints(q.cast<float>());
    const auto poses = link_poses(m, Eigen::VectorXd(q));
    for (size_t l = 0; l < m.links.size(); ++l) {
      const Eigen::Matrix4f ours = (base * poses[l].cast<float>()).matrix();
      CHECK((robot.link_pose(static_cast<int>(l)).matrix() - ours).cwiseAbs().maxCoeff() < 2e-5f);
    }
  }
}

TEST_CASE("A chain to an unknown link is an error naming the file", "[kinematics]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  CHECK_THROWS_WITH(KinematicChain(m, "tool0"), Catch::Contains("jaka_zu7.urdf") && Catch::Contains("tool0"));
}

TEST_CASE("The IK's position-only kinematics equal the full forward kinematics", "[kinematics][ik]") {
  // KinematicChain::tip_position takes shortcuts (a joint about a frame axis, a joint frame without
  // rotation); the Jaka (axes +-z, -y), the InMoov's right arm (+-x, +-y, +-z) and a chain with a
  // slanted axis and a slide check each against forward().
  const std::string mass = R"(<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>)";
  const RobotModel slanted = parse_urdf(R"(<robot name="r"><link name="a"/><link name="b">)" + mass + R"(</link>
    <link name="c">)" + mass + R"(</link><link name="d">)" + mass + R"(</link>
    <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.1" rpy="0.3 0 0.2"/>
      <axis xyz="0.6 0 0.8"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    <joint name="j2" type="prismatic"><parent link="b"/><child link="c"/><origin xyz="0.2 0 0"/>
      <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <joint name="j3" type="revolute"><parent link="c"/><child link="d"/><origin xyz="0 0.1 0" rpy="0 0.5 0"/>
      <axis xyz="0 0 -1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>)",
                                        "slanted.urdf");
  const RobotModel jaka = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  const RobotModel inmoov = load_urdf(test_asset("inmoov/inmoov.urdf"));
  const std::pair<const RobotModel*, const char*> chains[] = {{&jaka, "flange_link"}, {&inmoov, "r_hand_ee"}, {&slanted, "d"}};
  Rng rng(3);
  for (const auto& [model, tip_link] : chains) {
    const KinematicChain chain(*model, tip_link);
    INFO(tip_link << ", " << chain.dof() << " joints");
    for (int t = 0; t < 50; ++t) {
      const JointVector q = random_config(chain, rng);
      ChainJacobian full;
      PositionJacobian position;
      const Eigen::Vector3d tip = chain.forward(q, full).translation();
      CHECK((chain.tip_position(q, position) - tip).cwiseAbs().maxCoeff() < 1e-14);
      CHECK((position - full.topRows<3>()).cwiseAbs().maxCoeff() < 1e-14);
    }
  }
}
