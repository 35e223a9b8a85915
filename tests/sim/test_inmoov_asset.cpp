// The InMoov humanoid, tomato tree and obstacle column assets (assets/README.md), read through
// rdsim's own URDF loader and kinematics, as the environments will read them.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "rdsim/sim/ik.hpp"
#include "rdsim/sim/kinematics.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/robot.hpp"
#include "rdsim/sim/robot_model.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace {

using rdsim::JointType;
using rdsim::RobotModel;

std::string asset(const std::string& relative) {
  const char* root = std::getenv("RDSIM_ROOT");
  return std::string(root ? root : RDSIM_SOURCE_DIR) + "/assets/" + relative;
}

const RobotModel& inmoov() {
  static const RobotModel model = rdsim::load_urdf(asset("inmoov/inmoov.urdf"));
  return model;
}

const RobotModel& tomato_tree() {
  static const RobotModel model = rdsim::load_urdf(asset("objects/tomato_tree.urdf"));
  return model;
}

// Where assets/README.md says the tree stands in the InMoov's world frame (robot base at origin).
const Eigen::Vector3d kTreeBase(0.65, -0.20, 0.0);
constexpr double kTomatoReach = 0.55;  // m from the right shoulder, README's reachability promise

Eigen::Vector3d zero_pose_position(const RobotModel& model, const std::string& link) {
  return model.link_poses_at_zero()[static_cast<size_t>(model.require_link(link))].translation();
}

// The tomato links tomato_0, tomato_1, ... in order, stopping at the first missing index.
std::vector<int> tomato_links(const RobotModel& tree) {
  std::vector<int> out;
  for (int i = 0;; ++i) {
    const int link = tree.link_index("tomato_" + std::to_string(i));
    if (link < 0) return out;
    out.push_back(link);
  }
}

std::vector<Eigen::Vector3d> tomato_world_positions() {
  const RobotModel& tree = tomato_tree();
  const auto poses = tree.link_poses_at_zero();
  std::vector<Eigen::Vector3d> out;
  for (int link : tomato_links(tree)) out.push_back(kTreeBase + poses[static_cast<size_t>(link)].translation());
  return out;
}

// The far end of a link's first cylinder collision shape (its -z end), in the root frame.
Eigen::Vector3d cylinder_far_end(const RobotModel& model, const std::string& link) {
  const int i = model.require_link(link);
  const auto& shape = model.links[static_cast<size_t>(i)].collisions.at(0);
  REQUIRE(shape.type == rdsim::ShapeType::Cylinder);
  return model.link_poses_at_zero()[static_cast<size_t>(i)] * (shape.origin * Eigen::Vector3d(0, 0, -shape.length / 2));
}

}  // namespace

TEST_CASE("InMoov has more than 50 movable joints, all with human-range limits", "[assets][inmoov]") {
  const RobotModel& m = inmoov();
  CHECK(m.movable_joint_count() > 50);
  for (const auto& j : m.joints) {
    INFO("joint " << j.name);
    if (!j.movable()) continue;
    CHECK(j.type == JointType::Revolute);
    CHECK(std::isfinite(j.lower));
    CHECK(std::isfinite(j.upper));
    CHECK(j.lower < j.upper);
    // Human joints turn at most half a turn each way.
    CHECK(j.lower >= -M_PI - 1e-9);
    CHECK(j.upper <= M_PI + 1e-9);
    CHECK(j.effort > 0.0);
    CHECK(j.velocity > 0.0);
  }
}

TEST_CASE("every InMoov link has a physically plausible inertial", "[assets][inmoov]") {
  const RobotModel& m = inmoov();
  for (const auto& link : m.links) {
    INFO("link " << link.name);
    CHECK(link.inertial.mass > 0.0);
    const Eigen::Matrix3d& inertia = link.inertial.inertia;
    CHECK(inertia.isApprox(inertia.transpose()));
    const Eigen::Vector3d p = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia).eigenvalues();
    CHECK(p.minCoeff() > 0.0);
    // A real body's principal moments obey the triangle inequality.
    CHECK(p[0] + p[1] >= p[2] * (1 - 1e-9));
    // The principal moments fit a body no bigger than the robot: mass * (1 m)^2 bounds them.
    CHECK(p.maxCoeff() < link.inertial.mass * 1.0);
  }
  // README: 3D-printed upper body ~13 kg on an 8 kg pedestal.
  const double total = m.total_mass();
  const double moving = total - m.links[0].inertial.mass;
  CHECK(total > 10.0);
  CHECK(total < 40.0);
  CHECK(moving > 8.0);
  CHECK(moving < 25.0);
}

TEST_CASE("InMoov has life-size proportions, faces +x and stands on the floor", "[assets][inmoov]") {
  const RobotModel& m = inmoov();
  const Eigen::Vector3d r_shoulder = zero_pose_position(m, "r_shoulder");
  const Eigen::Vector3d l_shoulder = zero_pose_position(m, "l_shoulder");
  CHECK((l_shoulder - r_shoulder).norm() == Approx(0.40).margin(0.02));
  CHECK(r_shoulder.y() < 0.0);  // right arm on the robot's right when it faces +x
  CHECK(r_shoulder.z() == Approx(1.30).margin(0.02));

  const Eigen::Vector3d elbow = zero_pose_position(m, "r_forearm");
  const Eigen::Vector3d wrist = zero_pose_position(m, "r_wrist");
  CHECK((elbow - r_shoulder).norm() == Approx(0.28).margin(0.01));
  CHECK((wrist - elbow).norm() == Approx(0.26).margin(0.01));
  CHECK((cylinder_far_end(m, "r_middle_distal") - wrist).norm() == Approx(0.19).margin(0.01));

  // Eyes look forward: they sit at the front of the head.
  CHECK(zero_pose_position(m, "r_eye").x() > zero_pose_position(m, "head").x() + 0.05);

  // The root is the pedestal, resting on z = 0.
  const auto& base = m.links[0];
  CHECK(base.name == "base_link");
  REQUIRE(base.collisions.size() == 1);
  const auto& pedestal = base.collisions[0];
  CHECK(pedestal.origin.translation().z() - pedestal.size.z() / 2 == Approx(0.0).margin(1e-9));
}

TEST_CASE("InMoov's right-hand end effector sits at the palm on a fixed joint", "[assets][inmoov]") {
  const RobotModel& m = inmoov();
  for (const std::string side : {"r", "l"}) {
    const int ee = m.require_link(side + "_hand_ee");
    const auto& joint = m.joints[static_cast<size_t>(m.links[static_cast<size_t>(ee)].parent_joint)];
    CHECK(joint.type == JointType::Fixed);
    CHECK(m.links[static_cast<size_t>(joint.parent_link)].name == side + "_hand");
  }
  // The chain to it: torso (2) + arm (6).
  const rdsim::KinematicChain chain(m, "r_hand_ee");
  CHECK(chain.dof() == 8);
  // Within the palm box, on its face.
  const auto& palm = m.links[static_cast<size_t>(m.require_link("r_hand"))].collisions.at(0);
  const Eigen::Vector3d ee_in_palm =
      m.joints[static_cast<size_t>(m.links[static_cast<size_t>(m.require_link("r_hand_ee"))].parent_joint)]
          .origin.translation();
  const Eigen::Vector3d from_centre = ee_in_palm - palm.origin.translation();
  CHECK(std::abs(from_centre.x()) < 1e-9);
  CHECK(std::abs(from_centre.z()) < 1e-9);
  CHECK(std::abs(from_centre.y()) == Approx(palm.size.y() / 2));
}

TEST_CASE("InMoov's left side mirrors its right side for equal joint angles", "[assets][inmoov]") {
  // Every r_ arm/hand joint gets some angle inside its limits and its l_ twin the same angle;
  // then every l_ link must be the mirror image (through the x-z plane) of its r_ twin. This pins
  // down the left side's axis signs: a positive angle is the same anatomical motion on both
  // sides. The eyes are the exception (README): equal angles turn both the same way, for gaze.
  const RobotModel& m = inmoov();
  const auto is_eye = [](const std::string& name) { return name.find("_eye") != std::string::npos; };
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m.movable_joint_count());
  std::vector<int> dof_of(m.joints.size(), -1);
  for (size_t j = 0, k = 0; j < m.joints.size(); ++j)
    if (m.joints[j].movable()) dof_of[j] = static_cast<int>(k++);
  int paired = 0;
  for (size_t j = 0; j < m.joints.size(); ++j) {
    const auto& joint = m.joints[j];
    if (!joint.movable() || joint.name.rfind("r_", 0) != 0 || is_eye(joint.name)) continue;
    const int twin = m.joint_index("l_" + joint.name.substr(2));
    REQUIRE(twin >= 0);
    const double fraction = std::fmod(0.37 * static_cast<double>(j + 1), 1.0);
    const double angle = joint.lower + fraction * (joint.upper - joint.lower);
    q[dof_of[j]] = angle;
    q[dof_of[static_cast<size_t>(twin)]] = angle;
    ++paired;
  }
  CHECK(paired >= 20);  // two arms and two hands
  const auto poses = rdsim::link_poses(m, q);
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, -1, 1).asDiagonal();
  int compared = 0;
  for (size_t i = 0; i < m.links.size(); ++i) {
    if (m.links[i].name.rfind("r_", 0) != 0 || is_eye(m.links[i].name)) continue;
    const int twin = m.require_link("l_" + m.links[i].name.substr(2));
    INFO("link " << m.links[i].name);
    const auto& r = poses[i];
    const auto& l = poses[static_cast<size_t>(twin)];
    CHECK((l.translation() - mirror * r.translation()).norm() < 1e-9);
    CHECK((l.linear() - mirror * r.linear() * mirror).norm() < 1e-9);
    ++compared;
  }
  CHECK(compared >= 20);  // arm, wrist, palm, end effector and 16 finger links
}

TEST_CASE("InMoov's eyes turn together: equal angles give parallel gaze", "[assets][inmoov]") {
  const RobotModel& m = inmoov();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m.movable_joint_count());
  int dof = 0;
  for (const auto& joint : m.joints) {
    if (!joint.movable()) continue;
    if (joint.name.find("_eye_pan") != std::string::npos) q[dof] = 0.4;
    if (joint.name.find("_eye_tilt") != std::string::npos) q[dof] = -0.3;
    ++dof;
  }
  const auto poses = rdsim::link_poses(m, q);
  const auto& r = poses[static_cast<size_t>(m.require_link("r_eye"))];
  const auto& l = poses[static_cast<size_t>(m.require_link("l_eye"))];
  CHECK((r.linear() - l.linear()).norm() < 1e-9);
  // Positive pan looks left (+y) and negative tilt looks up, like the neck.
  const Eigen::Vector3d gaze = r.linear() * Eigen::Vector3d::UnitX();
  CHECK(gaze.y() > 0.3);
  CHECK(gaze.z() > 0.2);
}

TEST_CASE("tomato tree: a static tree with 5-8 tomato links on fixed joints named after them", "[assets][tomato]") {
  const RobotModel& tree = tomato_tree();
  CHECK(tree.movable_joint_count() == 0);
  const auto tomatoes = tomato_links(tree);
  CHECK(tomatoes.size() >= 5);
  CHECK(tomatoes.size() <= 8);
  for (size_t i = 0; i < tomatoes.size(); ++i) {
    const auto& link = tree.links[static_cast<size_t>(tomatoes[i])];
    INFO(link.name);
    const auto& joint = tree.joints[static_cast<size_t>(link.parent_joint)];
    CHECK(joint.name == "tomato_" + std::to_string(i));
    CHECK(joint.type == JointType::Fixed);
    CHECK(link.inertial.mass > 0.0);
    REQUIRE(link.collisions.size() == 1);
    CHECK(link.collisions[0].type == rdsim::ShapeType::Sphere);
    CHECK(link.collisions[0].radius >= 0.03);
    CHECK(link.collisions[0].radius <= 0.04);
    // The link frame is the tomato's centre, so an env can use the link position directly.
    CHECK(link.collisions[0].origin.translation().norm() < 1e-12);
    CHECK(link.visuals.at(0).rgba.x() > 0.6f);  // red
  }
  for (const auto& link : tree.links) CHECK(link.inertial.mass > 0.0);
}

TEST_CASE("every tomato is in front of the InMoov within reach of its right shoulder", "[assets][tomato]") {
  const Eigen::Vector3d shoulder = zero_pose_position(inmoov(), "r_shoulder");
  const auto tomatoes = tomato_world_positions();
  REQUIRE(tomatoes.size() >= 5);
  for (const auto& t : tomatoes) {
    INFO("tomato at " << t.transpose());
    CHECK((t - shoulder).norm() <= kTomatoReach);
    CHECK(t.x() > 0.25);  // in front of the chest (front face at x = 0.10)
  }
  // The tree stands clear of the robot: every InMoov link frame is well behind the trunk.
  for (const auto& pose : inmoov().link_poses_at_zero()) CHECK(pose.translation().x() < kTreeBase.x() - 0.15);
}

TEST_CASE("inverse kinematics brings the right palm to every tomato", "[assets][tomato]") {
  // The InMoov env moves the right hand with IK; every tomato must be a target it can reach. The
  // target is the point 1 cm off the tomato's surface on the shoulder's side: the hand cannot
  // go into the tomato, whose collision sphere is solid.
  const RobotModel& m = inmoov();
  const rdsim::KinematicChain chain(m, "r_hand_ee");
  rdsim::JointVector start = rdsim::JointVector::Zero(chain.dof());
  for (int i = 0; i < chain.dof(); ++i) {  // arm raised forward, elbow bent
    const std::string& name = m.joints[static_cast<size_t>(chain.model_joint(i))].name;
    if (name == "r_shoulder_lift") start[i] = 60.0 * M_PI / 180.0;
    if (name == "r_elbow") start[i] = 60.0 * M_PI / 180.0;
  }
  const Eigen::Vector3d shoulder = zero_pose_position(m, "r_shoulder");
  rdsim::IkOptions options;
  options.max_iterations = 300;
  for (const auto& t : tomato_world_positions()) {
    INFO("tomato at " << t.transpose());
    const Eigen::Vector3d target = t - (0.035 + 0.01) * (t - shoulder).normalized();
    const rdsim::IkResult result = rdsim::solve_ik(chain, target, start, options);
    CHECK(result.position_error < 0.005);
    CHECK((chain.forward(result.q).translation() - target).norm() < 0.005);
    CHECK((result.q.array() >= chain.lower().array() - 1e-12).all());
    CHECK((result.q.array() <= chain.upper().array() + 1e-12).all());
  }
}

TEST_CASE("InMoov holds its zero pose under gravity in the physics world", "[assets][inmoov][physics]") {
  // Bullet must accept the inertials (tiny finger links next to a 4 kg chest) and the position
  // motors must carry every link's weight with the documented efforts.
  rdsim::PhysicsWorld world;
  rdsim::Robot& robot = world.add_robot(inmoov(), Eigen::Isometry3f::Identity());
  REQUIRE(robot.dof() == inmoov().movable_joint_count());
  for (int i = 0; i < 240; ++i) world.step();  // 1 s
  const Eigen::VectorXf q = robot.joint_positions();
  const Eigen::VectorXf qdot = robot.joint_velocities();
  REQUIRE(q.allFinite());
  CHECK(q.cwiseAbs().maxCoeff() < 0.02f);
  CHECK(qdot.cwiseAbs().maxCoeff() < 0.05f);
  const Eigen::Vector3f ee = robot.link_pose(inmoov().require_link("r_hand_ee")).translation();
  CHECK((ee.cast<double>() - zero_pose_position(inmoov(), "r_hand_ee")).norm() < 0.01);
}

TEST_CASE("IK of the six right-arm joints, torso held, reaches every tomato from the env's home pose",
          "[assets][tomato]") {
  // What inmoov_tomato relies on, kinematically: its IK chain is the right arm only (the torso
  // joints on the path to the palm are frozen at their home angle, 0), and it starts from the env's
  // home pose (upper-arm rotation -30 deg, elbow 80 deg, wrist roll -30 deg: forearm forward). From
  // there the IK must put the palm centre on each tomato's approach point (1 cm outside the skin on
  // the side the palm comes from, inside the env's 6 cm success radius) within 2 mm, with every
  // joint inside its limits.
  // The physical reach (contacts with the tree) is tested by tests/envs/test_inmoov_tomato.cpp.
  const RobotModel& m = inmoov();
  RobotModel arm_only = m;  // same joint indices; torso frozen at its home angle 0
  for (auto& joint : arm_only.joints)
    if (joint.name == "mid_stomach" || joint.name == "top_stomach") joint.type = JointType::Fixed;
  const rdsim::KinematicChain chain(arm_only, "r_hand_ee");
  REQUIRE(chain.dof() == 6);
  rdsim::JointVector home = rdsim::JointVector::Zero(chain.dof());
  for (int i = 0; i < chain.dof(); ++i) {
    const std::string& name = m.joints[static_cast<size_t>(chain.model_joint(i))].name;
    INFO(name);
    CHECK(name.rfind("r_", 0) == 0);
    if (name == "r_upper_arm_rotate") home[i] = -30.0 * M_PI / 180.0;
    if (name == "r_elbow") home[i] = 80.0 * M_PI / 180.0;
    if (name == "r_wrist_roll") home[i] = -30.0 * M_PI / 180.0;
  }
  const Eigen::Vector3d palm_home = chain.forward(home).translation();
  constexpr double kRadius = 0.035;
  rdsim::IkOptions options;
  options.max_iterations = 300;
  options.tolerance = 1e-4;
  int index = 0;
  for (const auto& t : tomato_world_positions()) {
    INFO("tomato_" << index++ << " at " << t.transpose());
    const Eigen::Vector3d approach = t - (kRadius + 0.01) * (t - palm_home).normalized();
    const rdsim::IkResult result = rdsim::solve_ik(chain, approach, home, options);
    const Eigen::Vector3d palm = chain.forward(result.q).translation();
    INFO("palm " << palm.transpose() << ", q " << result.q.transpose());
    CHECK((palm - approach).norm() < 0.002);
    CHECK((result.q.array() >= chain.lower().array()).all());
    CHECK((result.q.array() <= chain.upper().array()).all());
    // The palm centre ends outside every tomato (it cannot go into a solid one).
    for (const auto& other : tomato_world_positions()) CHECK((palm - other).norm() > kRadius);
  }
}

TEST_CASE("obstacle column: one static cylinder 0.6 m high standing on its frame", "[assets][column]") {
  const RobotModel column = rdsim::load_urdf(asset("objects/column.urdf"));
  REQUIRE(column.links.size() == 1);
  CHECK(column.joints.empty());
  const auto& link = column.links[0];
  CHECK(link.inertial.mass > 0.0);
  REQUIRE(link.collisions.size() == 1);
  const auto& shape = link.collisions[0];
  CHECK(shape.type == rdsim::ShapeType::Cylinder);
  CHECK(shape.radius == Approx(0.05));
  CHECK(shape.length == Approx(0.6));
  CHECK(shape.origin.translation().z() - shape.length / 2 == Approx(0.0).margin(1e-9));
  // Its inertia is the solid cylinder's.
  const double m = link.inertial.mass;
  CHECK(link.inertial.inertia(0, 0) == Approx(m * (3 * 0.05 * 0.05 + 0.6 * 0.6) / 12));
  CHECK(link.inertial.inertia(2, 2) == Approx(m * 0.05 * 0.05 / 2));
}
