#include "rdsim/sim/kinematics.hpp"

#include <algorithm>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

// The joint's own motion: rotation about (or translation along) its axis, in its frame.
void apply_motion(Eigen::Isometry3d& frame, const Eigen::Vector3d& axis, bool prismatic, double q) {
  if (prismatic)
    frame.translation() += frame.linear() * (axis * q);
  else
    frame.linear() = frame.linear() * Eigen::AngleAxisd(q, axis).toRotationMatrix();
}

}  // namespace

KinematicChain::KinematicChain(const RobotModel& model, const std::string& tip_link)
    : tip_link_(model.require_link(tip_link)) {
  // Walk up from the tip, then replay the path from the root down.
  std::vector<int> path;  // joint indices, tip first
  for (int link = tip_link_; model.links[static_cast<size_t>(link)].parent_joint >= 0;) {
    const int j = model.links[static_cast<size_t>(link)].parent_joint;
    path.push_back(j);
    link = model.joints[static_cast<size_t>(j)].parent_link;
  }
  std::reverse(path.begin(), path.end());

  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();  // fixed transforms since the last joint
  lower_.resize(0);
  upper_.resize(0);
  std::array<double, kMaxChainDof> lo{}, hi{};
  for (int j : path) {
    const Joint& joint = model.joints[static_cast<size_t>(j)];
    pending = pending * joint.origin;
    if (!joint.movable()) continue;
    if (dof_ == kMaxChainDof)
      throw Error(model.source + ": the chain to link \"" + tip_link + "\" has more than " +
                  std::to_string(kMaxChainDof) + " movable joints");
    steps_[static_cast<size_t>(dof_)] = Step{pending, joint.axis, joint.type == JointType::Prismatic};
    model_joint_[static_cast<size_t>(dof_)] = j;
    lo[static_cast<size_t>(dof_)] = joint.lower;
    hi[static_cast<size_t>(dof_)] = joint.upper;
    ++dof_;
    pending = Eigen::Isometry3d::Identity();
  }
  tip_offset_ = pending;
  lower_.resize(dof_);
  upper_.resize(dof_);
  for (int i = 0; i < dof_; ++i) {
    lower_[i] = lo[static_cast<size_t>(i)];
    upper_[i] = hi[static_cast<size_t>(i)];
  }
}

Eigen::Isometry3d KinematicChain::forward(const JointVector& q) const {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  for (int i = 0; i < dof_; ++i) {
    const Step& s = steps_[static_cast<size_t>(i)];
    frame = frame * s.before;
    apply_motion(frame, s.axis, s.prismatic, q[i]);
  }
  return frame * tip_offset_;
}

Eigen::Isometry3d KinematicChain::forward(const JointVector& q, ChainJacobian& jacobian) const {
  std::array<Eigen::Vector3d, kMaxChainDof> axis_world, origin_world;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  for (int i = 0; i < dof_; ++i) {
    const Step& s = steps_[static_cast<size_t>(i)];
    frame = frame * s.before;
    axis_world[static_cast<size_t>(i)] = frame.linear() * s.axis;
    origin_world[static_cast<size_t>(i)] = frame.translation();
    apply_motion(frame, s.axis, s.prismatic, q[i]);
  }
  const Eigen::Isometry3d tip = frame * tip_offset_;
  jacobian.resize(6, dof_);
  for (int i = 0; i < dof_; ++i) {
    const Eigen::Vector3d& z = axis_world[static_cast<size_t>(i)];
    if (steps_[static_cast<size_t>(i)].prismatic) {
      jacobian.col(i) << z, Eigen::Vector3d::Zero();
    } else {
      jacobian.col(i) << z.cross(tip.translation() - origin_world[static_cast<size_t>(i)]), z;
    }
  }
  return tip;
}

std::vector<Eigen::Isometry3d> link_poses(const RobotModel& model, const Eigen::VectorXd& q) {
  if (q.size() != model.movable_joint_count())
    throw Error(model.source + ": expected " + std::to_string(model.movable_joint_count()) +
                " joint values, got " + std::to_string(q.size()));
  std::vector<Eigen::Isometry3d> poses(model.links.size(), Eigen::Isometry3d::Identity());
  int k = 0;
  for (size_t i = 1; i < model.links.size(); ++i) {
    const Joint& j = model.joints[i - 1];
    poses[i] = poses[static_cast<size_t>(j.parent_link)] * j.origin;
    if (j.movable()) apply_motion(poses[i], j.axis, j.type == JointType::Prismatic, q[k++]);
  }
  return poses;
}

}  // namespace rdsim
