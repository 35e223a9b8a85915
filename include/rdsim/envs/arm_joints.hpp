#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"
#include "rdsim/sim/robot_model.hpp"

// Which joints of a user's arm a task moves, checked against its URDF, shared by the envs that run
// any arm (reach: envs/reach_arm.hpp; the manipulation tasks: envs/manipulation/gripper_arm.hpp).
// Errors name the URDF file and the env key (env.effector_link, env.joints, env.home_pose).
namespace rdsim {

// The movable joints on the path from the root link to `link`, root first (RobotModel::joints indices).
std::vector<int> path_joints(const RobotModel& model, int link);

// The names of `joints` (RobotModel::joints indices), comma-separated.
std::string joint_list(const RobotModel& model, const std::vector<int>& joints);

// The controlled joints (RobotModel::joints indices, in home_pose order): `joints` (names), checked,
// or the whole path from the root link to `effector_link` when empty.
std::vector<int> controlled_joints(const RobotModel& model, const std::string& effector_link,
                                   const std::vector<std::string>& joints, const std::string& urdf);

// One value per robot dof (movable joints in model order, as Robot numbers them): `home` on the
// controlled joints (checked against their limits), 0 clamped into the limits elsewhere.
Eigen::VectorXf home_pose(const RobotModel& model, const std::vector<double>& home, const std::vector<int>& controlled,
                          const std::string& urdf);

// Three numbers of an option (checked to be three by its describe()) as a point, metres.
Eigen::Vector3f vector3(const std::vector<double>& xyz);

// The arm `arm` describes, its URDF at `urdf`, into `spec`: the robot file and mesh folders, the base
// pose, the effector link, the IK's joints and the home pose, each checked against the URDF (the
// errors above). Returns the robot's model.
RobotModel apply_arm_options(const ArmOptions& arm, const std::string& urdf, ReachTaskSpec& spec);

}  // namespace rdsim
