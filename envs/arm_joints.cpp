#include "rdsim/envs/arm_joints.hpp"

#include <algorithm>

#include "rdsim/core/error.hpp"
#include "rdsim/core/suggest.hpp"

namespace rdsim {

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
std::vector<int> controlled_joints(const RobotModel& model, const std::string& effector_link,
                                   const std::vector<std::string>& joints, const std::string& urdf) {
  const int ee = model.link_index(effector_link);
  if (ee < 0) {
    std::vector<std::string> links;
    for (const Link& l : model.links) links.push_back(l.name);
    throw Error(urdf + ": env.effector_link: the robot has no link \"" + one_line(effector_link, 60) + "\"" +
                did_you_mean(effector_link, links));
  }
  const std::vector<int> path = path_joints(model, ee);
  if (path.empty())
    throw Error(urdf + ": env.effector_link: no movable joint between the root link and \"" + effector_link + "\"");
  if (joints.empty()) return path;
  std::vector<int> out;
  for (const std::string& name : joints) {
    const int j = model.joint_index(name);
    if (j < 0 || std::find(path.begin(), path.end(), j) == path.end() ||
        std::find(out.begin(), out.end(), j) != out.end())
      throw Error(urdf + ": env.joints: \"" + one_line(name, 60) + "\" is " +
                  (j < 0 ? "not a joint of the robot" : std::find(out.begin(), out.end(), j) != out.end()
                                                             ? "listed twice"
                                                             : "not a movable joint on the path to the effector link") +
                  " (movable joints from the root to " + effector_link + ": " + joint_list(model, path) + ")");
    out.push_back(j);
  }
  return out;
}

// One value per robot dof (movable joints in model order, as Robot numbers them): home_pose on the
// controlled joints, 0 clamped into the limits elsewhere.
Eigen::VectorXf home_pose(const RobotModel& model, const std::vector<double>& home, const std::vector<int>& controlled,
                          const std::string& urdf) {
  if (home.size() != controlled.size())
    throw Error(urdf + ": env.home_pose: expected " + std::to_string(controlled.size()) +
                " values, one per controlled joint (" + joint_list(model, controlled) + "), got " +
                std::to_string(home.size()));
  Eigen::VectorXf q(model.movable_joint_count());
  int dof = 0;
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    if (!joint.movable()) continue;
    double value = std::clamp(0.0, joint.lower, joint.upper);
    const auto it = std::find(controlled.begin(), controlled.end(), static_cast<int>(j));
    if (it != controlled.end()) {
      value = home[static_cast<size_t>(it - controlled.begin())];
      if (joint.type != JointType::Continuous && (value < joint.lower || value > joint.upper))
        throw Error(urdf + ": env.home_pose: " + std::to_string(value) + " for joint " + joint.name +
                    " is outside its limits [" + std::to_string(joint.lower) + ", " + std::to_string(joint.upper) + "]");
    }
    q[dof++] = static_cast<float>(value);
  }
  return q;
}

Eigen::Vector3f vector3(const std::vector<double>& xyz) {
  return {static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2])};
}

RobotModel apply_arm_options(const ArmOptions& arm, const std::string& urdf, ReachTaskSpec& spec) {
  spec.robot_urdf = urdf;
  spec.package_paths = arm.package_paths;
  spec.base_pose = Eigen::Isometry3f(Eigen::Translation3f(vector3(arm.base_position)));
  spec.ee_link = arm.effector_link;
  RobotModel model = load_robot_urdf(spec);
  const std::vector<int> controlled = controlled_joints(model, arm.effector_link, arm.joints, urdf);
  for (int j : controlled) spec.ik_joints.push_back(model.joints[static_cast<size_t>(j)].name);
  spec.home = home_pose(model, arm.home_pose, controlled, urdf);
  return model;
}

}  // namespace rdsim
