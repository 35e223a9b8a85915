#pragma once
#include <string>
#include <vector>

#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/manipulation/manipulation_task.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"

// The robot half of a manipulation env: an arm with fingers (ArmOptions, ManipulationOptions::
// finger_joints) checked against its
// URDF, and the scene every task shares (table, floor, the task's cubes, goal markers) as the
// ReachTaskSpec that ReachTask simulates: the IK moves the effector and holds the home pose's
// orientation (ReachTaskSpec::effector_orientation), the fingers are driven apart from it.
//
// Errors (rdsim::Error naming the URDF file and the env key): an unknown effector link or arm joint
// (envs/arm_joints.hpp), a finger joint that is missing, not prismatic or on the arm's path, fingers
// whose stroke cannot open around a cube, a home pose of the wrong length or outside the limits or
// with the effector outside the workspace, a task area or goal range reaching outside the workspace.
namespace rdsim {

struct GripperArmScene {
  ReachTaskSpec spec;
  std::vector<int> finger_dofs;  // robot dofs (Robot numbering) of the finger joints
  std::vector<float> finger_lower, finger_upper;  // m, their limits
  TaskArea area;
};

// The scene of `task` for `config`'s ArmOptions and ManipulationOptions (loads the URDF).
GripperArmScene gripper_arm_scene(const EnvConfig& config, const ManipulationTask& task);

}  // namespace rdsim
