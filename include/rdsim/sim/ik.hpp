#pragma once
#include <Eigen/Cholesky>
#include <cmath>

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

// One damped-least-squares step: the joint change dq = J^T (J J^T + damping^2 I)^-1 e that best
// reduces the task error `e` (M values: 3 for a position, 6 for a pose) under the task Jacobian `j`
// (M x dof), with `damping` (m) keeping the step bounded near singular poses. Both solve_ik and
// the reaching envs' per-step moves (envs/reaching/reach_task.cpp) take their steps through this function.
// A template over the Jacobian's Eigen type, so a caller's block (ChainJacobian::topRows<3>())
// is used as it is, without a copy.
template <class Jacobian, class TaskError>
JointVector damped_least_squares_step(const Eigen::MatrixBase<Jacobian>& j, const Eigen::MatrixBase<TaskError>& e,
                                      double damping) {
  constexpr int M = TaskError::RowsAtCompileTime;
  static_assert(M == Jacobian::RowsAtCompileTime, "one Jacobian row per task error value");
  Eigen::Matrix<double, M, M> a = j * j.transpose();
  a.diagonal().array() += damping * damping;
  return j.transpose() * a.llt().solve(e);
}

// pybullet's calculateInverseKinematics with rest poses (lower/upper limits, joint ranges and rest
// poses given), as Bullet's source describes it (BussIK's damped least squares with a null-space
// term): each iteration takes the DLS step with damping 0.6 m plus the null-space velocity -- a pull
// of rest_gain x (rest - q), and for a joint beyond a limit a push of limit_gain x (limit - q) /
// (upper - lower) -- projected through (I - J^T (J J^T + damping^2 I)^-1 J), caps the largest joint
// change at max_joint_step, and stops once the error measured at the start of the previous
// iteration is within `tolerance`. Iterates are not clamped to the limits (pybullet's are not: the
// push brings a joint back), so the result may lie slightly outside them; the robot's targets are
// clamped. Used by the reaching envs' ik_method "null_space" (envs/reaching/reach_task.cpp). The chain holds
// only the joints between the root and the tip (pybullet's Jacobian has zero columns for the
// others, which then only feel the pull). tools/fidelity compares the two (docs/fidelity.md).
struct NullSpaceIkOptions {
  int iterations = 20;                 // pybullet's maxNumIterations default
  double damping = 0.6;                // m: BussIK's DefaultDampingLambda
  double rest_gain = 0.001;            // Bullet's stayCloseToZeroGain, per iteration
  double limit_gain = 10.0;            // Bullet's stayAwayFromLimitsGain, per iteration
  double max_joint_step = M_PI / 4.0;  // rad per iteration: BussIK's MaxAngleDLS (45 deg)
  double tolerance = 1e-4;             // m: pybullet's residualThreshold default
};

// Joint angles for the tip at `target` (root frame) from `start`, pulled towards `rest`.
JointVector null_space_ik(const KinematicChain& chain, const Eigen::Vector3d& target, const JointVector& start,
                          const JointVector& rest, const NullSpaceIkOptions& options = {});

// Tip position at `target` (root frame), starting from `start`.
IkResult solve_ik(const KinematicChain& chain, const Eigen::Vector3d& target, const JointVector& start,
                  const IkOptions& options = {});

// Tip position and orientation at `target` (root frame).
IkResult solve_ik(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& start,
                  const IkOptions& options = {});

}  // namespace rdsim
