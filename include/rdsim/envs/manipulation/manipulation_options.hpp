#pragma once
#include <string>
#include <vector>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/goal_layout.hpp"

// The options of the manipulation tasks (push, pick_and_place, stack, reach_goal): the task's rules,
// the fingers and the physics, one option group (core/env_options.hpp) in each task's defaults beside
// ArmOptions (envs/arm_options.hpp: which arm, shared with reach; by default the repo's JAKA Zu 7
// with rdsim's 85 mm parallel gripper, and any URDF whose fingers are prismatic joints, e.g.
// pybullet_data's Panda with finger_joints panda_finger_joint1/2). This describe() is the one
// declaration of these keys; envs/manipulation/manipulation_env.hpp implements them.
namespace rdsim {

inline const config::Names<GoalReward>& goal_reward_names() {
  static const config::Names<GoalReward> names = {
      {"sparse", GoalReward::Sparse}, {"partial", GoalReward::Partial}, {"dense", GoalReward::Dense}};
  return names;
}

// What the first action values command: effector moves (IK) or the arm's joints directly.
enum class ArmControl { Effector, Joints };

inline const config::Names<ArmControl>& arm_control_names() {
  static const config::Names<ArmControl> names = {{"effector", ArmControl::Effector}, {"joints", ArmControl::Joints}};
  return names;
}

// The initial values are the generic ones; each task publishes its own (push_defaults, ...).
struct ManipulationOptions {
  ArmControl control = ArmControl::Effector;
  double joint_step = 0.2;           // rad per step for a full action (control: joints)
  GoalReward reward_type = GoalReward::Sparse;
  double distance_threshold = 0.05;  // m
  bool block_gripper = false;
  std::vector<std::string> finger_joints{"finger_left_joint", "finger_right_joint"};
  double effector_step = 0.05;       // m per step for a full action
  std::vector<double> area_centre{0.45, 0.0};  // m, on the table (x, y)
  double object_range = 0.15;        // m, half-range of the cubes' start (x, y)
  double goal_range = 0.15;          // m, half-range of the goals (x, y)
  double goal_height = 0.0;          // m above the table: pick_and_place's air goals, reach_goal's range
  double finger_friction = 1.0;
  double object_friction = 1.0;
  double physics_step = 0.004;       // s
  int substeps = 10;                 // physics steps per env step (40 ms: panda-gym's control period)
};

template <class V, class C>
  requires config::Describes<C, ManipulationOptions>
void describe(V& v, C& c) {
  v.choice("reward_type", c.reward_type, goal_reward_names(),
           "sparse: -1 until every goal point is within distance_threshold of its goal, then 0; partial: minus the "
           "share of goal points not yet within it (stack: -0.5 with one cube placed; the same as sparse with one "
           "point); dense: minus the distance between the achieved and desired goal vectors (m). Success ends the episode (panda-gym's rule)");
  v.field("distance_threshold", c.distance_threshold, config::Range{1e-3, 1.0},
          "m; a goal point closer than this to its goal counts as reached (info.success)");
  v.choice("control", c.control, arm_control_names(),
           "effector: the first three action values move the effector (dx, dy, dz, effector_step each, by IK "
           "holding the gripper's orientation); joints: one value per arm joint (the IK chain's, in URDF order) "
           "moves that joint's target from where the joint is by up to joint_step, and the observation adds the "
           "joint positions (panda-gym's control_type \"joints\")");
  v.field("joint_step", c.joint_step, config::Range{1e-3, 1.0},
          "rad (m for a prismatic joint); control joints: an action value of 1 moves the joint's target this far "
          "from the joint's position");
  v.field("block_gripper", c.block_gripper,
          "the fingers stay closed and the action is Box(3) (effector moves only); false: Box(4), the 4th value "
          "the fingers' opening (-1 closed, 1 fully open)");
  v.field("finger_joints", c.finger_joints,
          "the fingers' prismatic joints, driven together: the opening is the sum of their positions above their "
          "lower limits (the pads touch at the lower limits); the grip force is their URDF effort");
  v.field("effector_step", c.effector_step, config::Range{1e-3, 0.5},
          "m; an action of 1 asks the effector to move this far along that axis in one env step (its goal, "
          "reached by IK that also holds the home pose's gripper orientation)");
  v.field("area_centre", c.area_centre, config::Range{-1e3, 1e3},
          "m: the centre (x, y) of the table area where cubes start and goals lie (the table top is z = 0)");
  v.field("object_range", c.object_range, config::Range{0.0, 1.0},
          "m; the cubes start at area_centre + U(-1, 1) x this in x and y");
  v.field("goal_range", c.goal_range, config::Range{0.0, 1.0},
          "m; goals are drawn at area_centre + U(-1, 1) x this in x and y");
  v.field("goal_height", c.goal_height, config::Range{0.0, 1.0},
          "m; pick_and_place: half the goals lie up to this high above a cube resting on the table; reach_goal: "
          "goals lie up to this high above the lowest effector height (workspace_min's z)");
  v.field("finger_friction", c.finger_friction, config::Range{0.0, 10.0},
          "friction coefficient of the finger links (a contact's is the product of both sides')");
  v.field("object_friction", c.object_friction, config::Range{0.0, 10.0}, "friction coefficient of the cubes");
  v.field("physics_step", c.physics_step, config::Range{1e-4, 0.05}, "s per physics step");
  v.field("substeps", c.substeps, config::Range{1, 1000},
          "physics steps per env step (an env step lasts physics_step x substeps s); the joints' drive closes as "
          "much of a move per env step with any count (its per-physics-step gain 1 - 0.7^(10 / substeps)), and "
          "with physics steps over 4 ms the solver solves the fingers' rows directly before up to 40 iterations "
          "(10 otherwise), which keeps the grasp down to 4 steps of 10 ms");
  v.check(c.area_centre.size() == 2, "area_centre", "expected 2 numbers (x, y)");
  v.check(!c.finger_joints.empty(), "finger_joints", "expected the names of the fingers' joints");
}

}  // namespace rdsim
