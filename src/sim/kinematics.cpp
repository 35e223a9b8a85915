#include "rdsim/sim/kinematics.hpp"

#include <algorithm>
#include <cmath>

#include "rdsim/core/error.hpp"
#include "sin_cos.hpp"

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
    Step& step = steps_[static_cast<size_t>(dof_)];
    step = Step{pending, joint.axis, joint.type == JointType::Prismatic};
    step.turns_before = !pending.linear().isIdentity(0.0);
    for (int k = 0; k < 3; ++k)
      if (std::abs(joint.axis[k]) == 1.0 && joint.axis.squaredNorm() == 1.0) {
        step.frame_axis = k;
        step.axis_sign = joint.axis[k];
      }
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

Eigen::Vector3d KinematicChain::tip_position(const JointVector& q, PositionJacobian& jacobian) const {
  // Every revolute joint's turn (about its frame axis, sign included, or its own axis), sines and
  // cosines in one batch: whole vectors of 8, the padding zeros.
  alignas(64) std::array<double, kMaxChainDof> turn{}, sines, cosines;
  for (int i = 0; i < dof_; ++i) {
    const Step& s = steps_[static_cast<size_t>(i)];
    turn[static_cast<size_t>(i)] = s.frame_axis >= 0 ? s.axis_sign * q[i] : q[i];
  }
  sin_cos(turn.data(), sines.data(), cosines.data(), (dof_ + 7) / 8 * 8);
  std::array<Eigen::Vector3d, kMaxChainDof> axis_world, origin_world;
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();  // the frame's rotation and origin (root frame)
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < dof_; ++i) {
    const Step& s = steps_[static_cast<size_t>(i)];
    p += r * s.before.translation();
    if (s.turns_before) r = r * s.before.linear();
    const auto k = static_cast<size_t>(i);
    axis_world[k] = s.frame_axis >= 0 ? Eigen::Vector3d(s.axis_sign * r.col(s.frame_axis)) : Eigen::Vector3d(r * s.axis);
    origin_world[k] = p;
    if (s.prismatic) {
      p += axis_world[k] * q[i];
    } else if (s.frame_axis >= 0) {
      // Rotation about frame axis a by angle t: the other two columns (b, c), in cyclic order,
      // turn in their plane: b' = cos t b + sin t c, c' = -sin t b + cos t c.
      const double c = cosines[static_cast<size_t>(i)], sn = sines[static_cast<size_t>(i)];
      const int b_col = (s.frame_axis + 1) % 3, c_col = (s.frame_axis + 2) % 3;
      const Eigen::Vector3d b0 = r.col(b_col), c0 = r.col(c_col);
      r.col(b_col) = c * b0 + sn * c0;
      r.col(c_col) = c * c0 - sn * b0;
    } else {  // Rodrigues: cos t I + sin t [a]x + (1 - cos t) a a^T
      const double c = cosines[static_cast<size_t>(i)], sn = sines[static_cast<size_t>(i)];
      const Eigen::Vector3d& a = s.axis;
      Eigen::Matrix3d turn_matrix = (1.0 - c) * a * a.transpose();
      turn_matrix.diagonal().array() += c;
      turn_matrix(0, 1) -= sn * a.z(), turn_matrix(1, 0) += sn * a.z();
      turn_matrix(0, 2) += sn * a.y(), turn_matrix(2, 0) -= sn * a.y();
      turn_matrix(1, 2) -= sn * a.x(), turn_matrix(2, 1) += sn * a.x();
      r = r * turn_matrix;
    }
  }
  const Eigen::Vector3d tip = p + r * tip_offset_.translation();
  jacobian.resize(3, dof_);
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<size_t>(i);
    jacobian.col(i) = steps_[k].prismatic ? axis_world[k] : Eigen::Vector3d(axis_world[k].cross(tip - origin_world[k]));
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
