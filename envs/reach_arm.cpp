#include "rdsim/envs/reach_arm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rdsim/core/error.hpp"
#include "rdsim/core/suggest.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace rdsim {
namespace {

Eigen::Vector3f vec3(const std::vector<double>& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

std::string point_text(const Eigen::Vector3f& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", p.x(), p.y(), p.z());
  return text;
}

// The movable joints on the path from the root link to `link`, root first (RobotModel::joints indices).
std::vector<int> path_joints(const RobotModel& model, int link) {
  std::vector<int> out;
  for (int l = link; model.links[static_cast<size_t>(l)].parent_joint >= 0;) {
    const int j = model.links[static_cast<size_t>(l)].parent_joint;
    if (model.joints[static_cast<size_t>(j)].movable()) out.push_back(j);
    l = model.joints[static_cast<size_t>(j)].parent_link;
  }
  std::reverse(out.begin(), out.end());
  return out;
}

std::string joint_list(const RobotModel& model, const std::vector<int>& joints) {
  std::string s;
  for (int j : joints) s += (s.empty() ? "" : ", ") + model.joints[static_cast<size_t>(j)].name;
  return s;
}

// The controlled joints (RobotModel::joints indices, in home_pose order): env.joints, checked, or the
// whole path to the effector.
std::vector<int> controlled_joints(const RobotModel& model, const ArmOptions& arm, const std::string& urdf) {
  const int ee = model.link_index(arm.effector_link);
  if (ee < 0) {
    std::vector<std::string> links;
    for (const Link& l : model.links) links.push_back(l.name);
    throw Error(urdf + ": env.effector_link: the robot has no link \"" + one_line(arm.effector_link, 60) + "\"" +
                did_you_mean(arm.effector_link, links));
  }
  const std::vector<int> path = path_joints(model, ee);
  if (path.empty())
    throw Error(urdf + ": env.effector_link: no movable joint between the root link and \"" + arm.effector_link + "\"");
  if (arm.joints.empty()) return path;
  std::vector<int> out;
  for (const std::string& name : arm.joints) {
    const int j = model.joint_index(name);
    if (j < 0 || std::find(path.begin(), path.end(), j) == path.end() ||
        std::find(out.begin(), out.end(), j) != out.end())
      throw Error(urdf + ": env.joints: \"" + one_line(name, 60) + "\" is " +
                  (j < 0 ? "not a joint of the robot" : std::find(out.begin(), out.end(), j) != out.end()
                                                             ? "listed twice"
                                                             : "not a movable joint on the path to the effector link") +
                  " (movable joints from the root to " + arm.effector_link + ": " + joint_list(model, path) + ")");
    out.push_back(j);
  }
  return out;
}

// One value per robot dof (movable joints in model order, as Robot numbers them): home_pose on the
// controlled joints, 0 clamped into the limits elsewhere.
Eigen::VectorXf home_pose(const RobotModel& model, const ArmOptions& arm, const std::vector<int>& controlled,
                          const std::string& urdf) {
  if (arm.home_pose.size() != controlled.size())
    throw Error(urdf + ": env.home_pose: expected " + std::to_string(controlled.size()) +
                " values, one per controlled joint (" + joint_list(model, controlled) + "), got " +
                std::to_string(arm.home_pose.size()));
  Eigen::VectorXf q(model.movable_joint_count());
  int dof = 0;
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    if (!joint.movable()) continue;
    double value = std::clamp(0.0, joint.lower, joint.upper);
    const auto it = std::find(controlled.begin(), controlled.end(), static_cast<int>(j));
    if (it != controlled.end()) {
      value = arm.home_pose[static_cast<size_t>(it - controlled.begin())];
      if (joint.type != JointType::Continuous && (value < joint.lower || value > joint.upper))
        throw Error(urdf + ": env.home_pose: " + std::to_string(value) + " for joint " + joint.name +
                    " is outside its limits [" + std::to_string(joint.lower) + ", " + std::to_string(joint.upper) + "]");
    }
    q[dof++] = static_cast<float>(value);
  }
  return q;
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
  s.robot_urdf = arm_urdf(config);
  s.package_paths = arm.package_paths;
  s.base_pose = Eigen::Isometry3f(Eigen::Translation3f(vec3(arm.base_position)));
  s.ee_link = arm.effector_link;
  const RobotModel model = load_robot_urdf(s);
  const std::vector<int> controlled = controlled_joints(model, arm, s.robot_urdf);
  for (int j : controlled) s.ik_joints.push_back(model.joints[static_cast<size_t>(j)].name);
  s.home = home_pose(model, arm, controlled, s.robot_urdf);
  const Eigen::Vector3f centre = vec3(arm.target_centre);
  s.statics = {{assets + "/objects/floor.urdf", Eigen::Isometry3f::Identity()},
               {assets + "/objects/target_marker.urdf", Eigen::Isometry3f(Eigen::Translation3f(centre))}};
  s.target_body = ReachArm::marker_index;
  s.nominal_target = centre;
  s.target_half_range = vec3(arm.target_half_range);
  s.workspace = Eigen::AlignedBox3f(vec3(arm.workspace_min), vec3(arm.workspace_max));
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
