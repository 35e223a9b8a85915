#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "rdsim/sim/robot_model.hpp"

// Forward kinematics of robot models, our own (not Bullet's): a chain is precomputed once so
// that FK and its Jacobian are a handful of fixed-size products per joint, with no allocation.
namespace rdsim {

constexpr int kMaxChainDof = 16;  // arms and hands; a whole humanoid is several chains

// Joint values of a chain and its Jacobian: fixed-capacity Eigen types, never heap-allocated.
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxChainDof, 1>;
using ChainJacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxChainDof>;
using PositionJacobian = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, kMaxChainDof>;

// The movable joints on the path from a model's root link to one link (the "tip", e.g. a
// flange). Poses are in the root link's frame.
class KinematicChain {
public:
  // rdsim::Error when the tip link does not exist or the path has more than kMaxChainDof joints.
  KinematicChain(const RobotModel& model, const std::string& tip_link);

  int dof() const { return dof_; }
  int tip_link() const { return tip_link_; }
  int model_joint(int i) const { return model_joint_[static_cast<size_t>(i)]; }  // index into RobotModel::joints
  const JointVector& lower() const { return lower_; }
  const JointVector& upper() const { return upper_; }
  JointVector clamp(const JointVector& q) const { return q.cwiseMax(lower_).cwiseMin(upper_); }

  Eigen::Isometry3d forward(const JointVector& q) const;
  // Also the geometric Jacobian of the tip: rows 0-2 map joint speeds to its linear velocity,
  // rows 3-5 to its angular velocity (root frame).
  Eigen::Isometry3d forward(const JointVector& q, ChainJacobian& jacobian) const;
  // The tip's position and the position rows of its Jacobian only: the same kinematics as
  // forward(), for an IK's inner loop (a joint about a frame axis turns two columns of the frame,
  // a joint frame without rotation adds only its offset). Equal to forward()'s to rounding.
  Eigen::Vector3d tip_position(const JointVector& q, PositionJacobian& jacobian) const;

private:
  struct Step {
    Eigen::Isometry3d before;  // from the previous joint's frame (after its motion) to this joint's frame
    Eigen::Vector3d axis;      // in this joint's frame
    bool prismatic = false;
    bool turns_before = true;  // `before` has a rotation (else it is a pure offset)
    int frame_axis = -1;       // axis is +-(this frame axis) exactly: 0, 1, 2; -1 otherwise
    double axis_sign = 1.0;
  };
  int dof_ = 0;
  int tip_link_ = -1;
  std::array<Step, kMaxChainDof> steps_{};
  std::array<int, kMaxChainDof> model_joint_{};
  Eigen::Isometry3d tip_offset_ = Eigen::Isometry3d::Identity();  // last joint frame to the tip
  JointVector lower_, upper_;
};

// Every link's frame relative to the root for the model's movable joints set to `q` (tree
// order, one value per movable joint). For renderers and tests; allocates.
std::vector<Eigen::Isometry3d> link_poses(const RobotModel& model, const Eigen::VectorXd& q);

}  // namespace rdsim
