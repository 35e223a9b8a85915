#include "rdsim/sim/robot_model.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {

int RobotModel::link_index(std::string_view link_name) const {
  for (size_t i = 0; i < links.size(); ++i)
    if (links[i].name == link_name) return static_cast<int>(i);
  return -1;
}

int RobotModel::joint_index(std::string_view joint_name) const {
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == joint_name) return static_cast<int>(i);
  return -1;
}

int RobotModel::require_link(std::string_view link_name) const {
  const int i = link_index(link_name);
  if (i < 0) throw Error(source + ": robot \"" + name + "\" has no link \"" + std::string(link_name) + "\"");
  return i;
}

int RobotModel::movable_joint_count() const {
  int n = 0;
  for (const auto& j : joints) n += j.movable() ? 1 : 0;
  return n;
}

double RobotModel::total_mass() const {
  double m = 0.0;
  for (const auto& l : links) m += l.inertial.mass;
  return m;
}

std::vector<Eigen::Isometry3d> RobotModel::link_poses_at_zero() const {
  std::vector<Eigen::Isometry3d> poses(links.size(), Eigen::Isometry3d::Identity());
  for (size_t i = 1; i < links.size(); ++i) {
    const Joint& j = joints[i - 1];
    poses[i] = poses[static_cast<size_t>(j.parent_link)] * j.origin;
  }
  return poses;
}

}  // namespace rdsim
