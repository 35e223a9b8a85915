#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"

// Optional capability of an Env whose world is a robot (implemented next to rdsim::Env, like
// EnvState; find it with dynamic_cast<RobotControl*>(&env)): what a person or another program
// needs to drive the robot by hand instead of through the env's action space. The reaching envs
// (envs/reach_env.hpp) implement it in-process and RemoteEnv (remote/remote_env.hpp) over the
// network link, so a teleoperation window, `rdsim serve` and tools/rdsim_client.py all speak it.
//
// Frames and units: world frame (z up), metres, radians (metres for prismatic joints), seconds.
// Joints are the robot's movable joints in "dof" order (the URDF's tree order), the same order
// in RobotInfo::joints, RobotSnapshot and set_joint_targets.
//
// Control calls are env steps: move_effector and set_joint_targets set the drive's joint
// targets, advance the world by one control period (Spec::control_dt: action_repeat physics
// steps) and judge the step exactly as Env::step does (reward, success, collision, out of bounds,
// the step limit). So they count towards Spec::max_episode_steps, and after an episode ends they
// move nothing and report terminated until Env::reset. To move in real time, call one of them
// every control_dt seconds; repeating the same target keeps the arm going towards it (the joint
// drives are speed-limited, so a far target takes many steps).
namespace rdsim {

enum class JointKind { Revolute, Continuous, Prismatic };

struct JointInfo {
  std::string name;         // the URDF joint name
  JointKind kind = JointKind::Revolute;
  float lower = 0, upper = 0;  // position limits (rad or m); continuous joints: -inf, +inf
  float max_velocity = 0;      // the URDF speed limit (rad/s or m/s); 0 when the URDF has none
};

// A camera of the robot's world: fixed to a robot link (moves with it: an InMoov eye, the camera on
// the Jaka's wrist) or, with an empty link, fixed in the world ("scene": the env's main view, for
// watching the whole task).
struct CameraInfo {
  std::string name;   // "left_eye", "right_eye", "wrist", "scene"
  std::string link;   // the URDF link it is fixed to; "" = fixed in the world
  float fov_deg = 60; // vertical field of view; the horizontal one follows from the image's aspect
};

// What does not change while the env lives.
struct RobotInfo {
  std::string robot;          // the URDF's robot name
  std::string effector_link;  // the link move_effector positions (its frame origin)
  std::vector<JointInfo> joints;
  std::vector<CameraInfo> cameras;
  // Effector targets are clipped into this box (world frame, m); leaving it by the env's margin
  // ends an episode (out of bounds).
  Eigen::AlignedBox3f workspace;
};

struct BodyPose {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
};

// A snapshot of the robot, as of the last step or reset.
struct RobotSnapshot {
  Eigen::VectorXf joint_positions;   // one per RobotInfo::joints
  Eigen::VectorXf joint_velocities;  // rad/s or m/s
  Eigen::VectorXf joint_targets;     // the drive's position targets
  Eigen::Vector3f effector_position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf effector_orientation = Eigen::Quaternionf::Identity();
  Eigen::Vector3f target = Eigen::Vector3f::Zero();  // the task's target point
  int steps = 0;                                     // env steps in this episode
  // Where the task's other bodies are (table, button, cubes, goal markers: the env's static and
  // free bodies, in its order, world frame): what a copy of the scene needs to draw it.
  std::vector<BodyPose> bodies;
};

class RobotControl {
public:
  virtual ~RobotControl() = default;

  virtual const RobotInfo& robot_info() const = 0;
  // Non-const: a remote implementation asks over the network.
  virtual RobotSnapshot robot_state() = 0;

  // The original RobotDrlSim `position` command: the effector to the absolute point `position`
  // (clipped into RobotInfo::workspace), by inverse kinematics on the env's IK joints solved from
  // the current joint angles; no move noise. One env step. rdsim::Error for a non-finite value.
  virtual StepResult move_effector(const Eigen::Vector3f& position) = 0;

  // Absolute position targets for every joint (RobotInfo::joints order), each clamped to its
  // limits. One env step. rdsim::Error for the wrong count or a non-finite value.
  virtual StepResult set_joint_targets(const Eigen::VectorXf& targets) = 0;

  // What camera `camera` (index into RobotInfo::cameras) sees now, as an RGB image
  // of width x height (row 0 at the top). rdsim::Error for an unknown camera or a size outside
  // 1..max_camera_side.
  virtual void camera_image(int camera, int width, int height, Image& out) = 0;

  static constexpr int max_camera_side = 4096;
};

inline const char* to_string(JointKind kind) {
  return kind == JointKind::Prismatic ? "prismatic" : kind == JointKind::Continuous ? "continuous" : "revolute";
}

}  // namespace rdsim
