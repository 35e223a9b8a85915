#include "rdsim/envs/reaching/reach_arm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rdsim/core/error.hpp"
#include "rdsim/envs/arm_joints.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace rdsim {
namespace {

std::string point_text(const Eigen::Vector3f& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", p.x(), p.y(), p.z());
  return text;
}

ReachTerms arm_terms(const ReachTaskSpec& spec) {
  return ReachTerms{.main_view = arm_main_view(spec.workspace), .second_view = arm_second_view(spec.workspace)};
}

}  // namespace

EnvConfig reach_arm_defaults() {
  EnvConfig c = reach_env_config(EnvConfig{.name = "reach", .max_steps = 200}, ReachOptions{.max_distance = 1.0});
  c.options.emplace_back(ArmOptions{});
  return c;
}

std::string arm_urdf(const EnvConfig& config) {
  const std::string& urdf = config.get<ArmOptions>().urdf;
  return urdf.empty() ? asset_root(config.get<ReachOptions>()) + "/jaka/jaka_zu7.urdf" : urdf;
}

OrbitView arm_main_view(const Eigen::AlignedBox3f& workspace) {
  return OrbitView{.target = workspace.center(),
                   .distance = 0.8f * workspace.diagonal().norm(),
                   .yaw_deg = 155.0f,
                   .pitch_deg = -36.0f};
}

OrbitView arm_second_view(const Eigen::AlignedBox3f& workspace) {
  return OrbitView{.target = workspace.center(),
                   .distance = 0.8f * workspace.diagonal().norm(),
                   .yaw_deg = 32.0f,
                   .pitch_deg = -13.0f};
}

ReachTaskSpec reach_arm_spec(const EnvConfig& config) {
  const ArmOptions& arm = config.get<ArmOptions>();
  const std::string assets = asset_root(config.get<ReachOptions>());
  ReachTaskSpec s;
  s.name = "reach";
  apply_arm_options(arm, arm_urdf(config), s);
  const Eigen::Vector3f centre = vector3(arm.target_centre);
  s.statics = {{assets + "/objects/floor.urdf", Eigen::Isometry3f::Identity()},
               {assets + "/objects/target_marker.urdf", Eigen::Isometry3f(Eigen::Translation3f(centre))}};
  s.target_body = ReachArm::marker_index;
  s.nominal_target = centre;
  s.target_half_range = vector3(arm.target_half_range);
  s.workspace = Eigen::AlignedBox3f(vector3(arm.workspace_min), vector3(arm.workspace_max));
  apply_env_config(config, s);
  return s;
}

ReachArm::ReachArm(const EnvConfig& config) : ReachArm(reach_arm_spec(config), config) {}

ReachArm::ReachArm(const ReachTaskSpec& spec, const EnvConfig& config) : ReachEnv(spec, arm_terms(spec), config) {
  // An episode that starts out of bounds would end at its first step.
  const Eigen::Vector3f& ee = task().ee_position();
  if (spec.workspace_bounds && spec.workspace.exteriorDistance(ee) > spec.workspace_margin)
    throw Error(spec.robot_urdf + ": env.home_pose puts " + spec.ee_link + " at " + point_text(ee) +
                ", outside the workspace box " + point_text(spec.workspace.min()) + " .. " +
                point_text(spec.workspace.max()) + " (workspace_min, workspace_max)");
}

std::unique_ptr<Env> make_reach_arm(const EnvConfig& config) { return std::make_unique<ReachArm>(config); }

}  // namespace rdsim
