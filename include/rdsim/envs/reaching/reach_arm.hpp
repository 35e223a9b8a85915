#pragma once
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/render/camera.hpp"

// reach — the reaching task for any arm: the robot of env.urdf (ArmOptions, envs/arm_options.hpp)
// moves its effector link to a target point by IK moves, under the same rules as the other
// reaching envs (ReachEnv, ReachOptions). Defaults: the repo's Jaka Zu 7, so `{"name": "reach"}`
// runs as it is; a user's arm sets urdf, effector_link, home_pose and the boxes.
//
// Scene (world frame, z up, metres): the floor's top is the plane z = 0 (assets/objects/floor.urdf);
// the robot's root link at base_position; the target marker (assets/objects/target_marker.urdf, a
// red sphere of radius 2 cm that nothing collides with) at the target point.
// Target: target_centre; random_target: target_centre + U(-1, 1) x target_half_range per axis, drawn
// from the env's Rng at each reset. The whole range must lie in the workspace box.
// Joints: `joints` (or every movable joint from the root link to effector_link) are the IK's; their
// home values are home_pose, in that order; every other movable joint holds 0 clamped into its
// limits. reset_pose rest is home here (no separate rest pose).
// Observation (ground truth, full layout): target - effector (3), effector position (3).
// raw_pixels: two cameras framing the workspace box from the front-left (main: yaw 155 deg, pitch
// -36 deg) and the right (second, multi_view: yaw 32 deg, pitch -13 deg), fov 60 deg, aimed at the
// box's centre from 0.8 x its diagonal.
// Reward -|effector - target| (m) per step; success, bounds and truncation as ReachEnv says.
// Errors: an unknown effector link or joint, a joint off the path, a home pose of the wrong length
// or outside the joint limits, a home pose that puts the effector outside the workspace box (with
// workspace_bounds): rdsim::Error naming the URDF file and the key.
namespace rdsim {

// reach's published defaults: core's, ReachOptions (max_distance 1 m) and ArmOptions (the Jaka).
EnvConfig reach_arm_defaults();

// The robot's URDF path: env.urdf, or the repo's Jaka when empty.
std::string arm_urdf(const EnvConfig& config);

// The scene and numbers above from `config` (loads the URDF to check the joints and the home pose).
ReachTaskSpec reach_arm_spec(const EnvConfig& config);

// Cameras framing the workspace box (see above).
OrbitView arm_main_view(const Eigen::AlignedBox3f& workspace);
OrbitView arm_second_view(const Eigen::AlignedBox3f& workspace);

class ReachArm final : public ReachEnv {
public:
  explicit ReachArm(const EnvConfig& config);
  static constexpr int floor_index = 0;   // index in task().spec().statics
  static constexpr int marker_index = 1;  // the target marker

private:
  ReachArm(const ReachTaskSpec& spec, const EnvConfig& config);
};

std::unique_ptr<Env> make_reach_arm(const EnvConfig& config);

}  // namespace rdsim
