#pragma once
#include <string>
#include <vector>

#include "rdsim/core/config_fields.hpp"

// Which arm runs a task and where: the options of the envs that take any arm, the generic reach env
// ("reach", envs/reach_arm.hpp) and the manipulation tasks (envs/manipulation/manipulation_env.hpp).
// One option group (core/env_options.hpp) in their defaults, beside the task's own rules
// (ReachOptions; ManipulationOptions). The defaults describe the repo's Jaka Zu 7 (the manipulation
// tasks: with rdsim's gripper), the example arm: a user's arm sets at least urdf, effector_link,
// home_pose and the boxes.
namespace rdsim {

struct ArmOptions {
  std::string urdf{};                        // "" = the repo's Jaka Zu 7 (asset_root()/jaka/jaka_zu7.urdf)
  std::vector<std::string> package_paths{};  // folders for package:// and relative mesh paths
  std::string effector_link = "flange_link";
  std::vector<std::string> joints{};         // controlled joints; empty = every movable joint root -> effector
  std::vector<double> home_pose{-0.26, 1.44, -1.85, 1.98, 1.5708, 0.0};  // rad (m), one per controlled joint
  std::vector<double> base_position{0.0, 0.0, 0.0};                      // m, world
  std::vector<double> workspace_min{0.15, -0.5, 0.02};                   // m, world
  std::vector<double> workspace_max{0.85, 0.5, 0.55};                    // m, world
  std::vector<double> target_centre{0.5, 0.0, 0.15};                     // m, world
  std::vector<double> target_half_range{0.15, 0.3, 0.1};                 // m, per axis
  // Not a key: whether the task has reach's target point, so that target_centre and
  // target_half_range are keys (reach) or not (the manipulation tasks draw their goals themselves).
  bool has_target = true;
};

// Whether the three-number lists hold three numbers, workspace_min lies below workspace_max on every
// axis, and the target range (target_centre +- target_half_range) inside that box.
inline bool arm_boxes_sized(const ArmOptions& c) {
  return c.base_position.size() == 3 && c.workspace_min.size() == 3 && c.workspace_max.size() == 3 &&
         c.target_centre.size() == 3 && c.target_half_range.size() == 3;
}
inline bool arm_workspace_ordered(const ArmOptions& c) {
  for (size_t i = 0; i < 3; ++i)
    if (!(c.workspace_min[i] < c.workspace_max[i])) return false;
  return true;
}
inline bool arm_targets_inside(const ArmOptions& c) {
  if (!c.has_target) return true;
  for (size_t i = 0; i < 3; ++i)
    if (c.target_centre[i] - c.target_half_range[i] < c.workspace_min[i] ||
        c.target_centre[i] + c.target_half_range[i] > c.workspace_max[i])
      return false;
  return true;
}

template <class V, class C>
  requires config::Describes<C, ArmOptions>
void describe(V& v, C& c) {
  constexpr double big = 1e3;  // m: any box a robot arm works in
  v.field("urdf", c.urdf,
          "the robot's URDF file; a relative path in a config file is relative to that file's folder (in code "
          "or Python: to the current directory); empty = the repo's Jaka Zu 7 (with rdsim's 85 mm parallel gripper "
          "in the manipulation tasks), the arm the other defaults fit");
  v.field("package_paths", c.package_paths,
          "folders searched for the URDF's package:// and relative mesh paths, in order (relative ones as urdf)");
  v.field("effector_link", c.effector_link,
          "the link the actions move (its frame origin): to the target in reach; the point between the finger pads "
          "in the manipulation tasks");
  v.field("joints", c.joints,
          "the joints the IK moves (names, each on the path from the root link to effector_link); empty = every "
          "movable joint on that path. Other movable joints hold their home value");
  v.field("home_pose", c.home_pose, config::Range{-big, big},
          "rad (m for prismatic joints): where episodes start, one value per controlled joint in the order of "
          "joints (empty joints: root to effector); movable joints not controlled hold 0 clamped into their limits "
          "(the manipulation tasks' fingers start open, and the gripper keeps this pose's orientation)");
  v.field("base_position", c.base_position, config::Range{-big, big}, "m: the robot's root link in the world (x, y, z)");
  v.field("workspace_min", c.workspace_min, config::Range{-big, big},
          "m: lower corner (x, y, z) of the box move goals are clipped into (reach: the floor is the plane z = 0; "
          "the manipulation tasks: the table top)");
  v.field("workspace_max", c.workspace_max, config::Range{-big, big}, "m: its upper corner (x, y, z)");
  if (c.has_target) {
    v.field("target_centre", c.target_centre, config::Range{-big, big},
            "m: the target (x, y, z); random_target draws around it");
    v.field("target_half_range", c.target_half_range, config::Range{0.0, big},
            "m: random_target adds U(-1, 1) x this per axis; the whole range must lie in the workspace box");
  }
  v.check(c.base_position.size() == 3, "base_position", "expected 3 numbers (x, y, z)");
  v.check(c.workspace_min.size() == 3, "workspace_min", "expected 3 numbers (x, y, z)");
  v.check(c.workspace_max.size() == 3, "workspace_max", "expected 3 numbers (x, y, z)");
  v.check(!c.has_target || c.target_centre.size() == 3, "target_centre", "expected 3 numbers (x, y, z)");
  v.check(!c.has_target || c.target_half_range.size() == 3, "target_half_range", "expected 3 numbers (x, y, z)");
  v.check(!arm_boxes_sized(c) || arm_workspace_ordered(c), "workspace_max",
          "expected each value above workspace_min's");
  v.check(!arm_boxes_sized(c) || arm_targets_inside(c), "target_centre",
          "the target range (target_centre +- target_half_range) reaches outside the workspace box "
          "(workspace_min .. workspace_max)");
}

// Makes urdf and package_paths, when relative, absolute paths relative to `folder` (a config file's
// folder: read_train_config through resolve_env_paths), so the resolved config.json points at the
// same files from any folder.
void resolve_arm_paths(ArmOptions& options, const std::string& folder);

}  // namespace rdsim
