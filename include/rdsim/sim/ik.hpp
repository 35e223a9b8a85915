#pragma once
#include "rdsim/sim/kinematics.hpp"

// Inverse kinematics by damped least squares (Levenberg-Marquardt: the damping grows when a
// step makes things worse and shrinks when it helps). Joint limits are respected by clamping
// every iterate. All fixed-size Eigen; an env can call it every step.
namespace rdsim {

struct IkOptions {
  int max_iterations = 100;
  double tolerance = 1e-4;              // m: stop when the tip is this close to the target
  double orientation_tolerance = 1e-3;  // rad (pose targets only)
  // Metres of position error that one radian of orientation error counts as (pose targets).
  double orientation_weight = 0.2;
  double damping = 0.02;      // initial damping, metres
  double max_joint_step = 0.5;  // rad (or m) per iteration, so far targets are approached in stages
  // Far targets from arbitrary starts can end in a local minimum (a joint limit folds the arm
  // the wrong way). When not converged, retry up to this many times from fixed pseudo-random
  // configurations (deterministic) and keep the best. 0 for per-step use from the current pose.
  int restarts = 0;
};

struct IkResult {
  JointVector q;
  double position_error = 0.0;     // m
  double orientation_error = 0.0;  // rad (0 for position targets)
  int iterations = 0;  // over all attempts
  bool converged = false;
};

// Tip position at `target` (root frame), starting from `start`.
IkResult solve_ik(const KinematicChain& chain, const Eigen::Vector3d& target, const JointVector& start,
                  const IkOptions& options = {});

// Tip position and orientation at `target` (root frame).
IkResult solve_ik(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& start,
                  const IkOptions& options = {});

}  // namespace rdsim
