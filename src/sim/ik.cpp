#include "rdsim/sim/ik.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rdsim/core/rng.hpp"

namespace rdsim {
namespace {

// M = 3: position task; M = 6: position + weighted orientation task.
template <int M>
class Task {
public:
  using Error = Eigen::Matrix<double, M, 1>;
  using Jacobian = Eigen::Matrix<double, M, Eigen::Dynamic, Eigen::ColMajor, M, kMaxChainDof>;

  Task(const KinematicChain& chain, const Eigen::Isometry3d& target, const IkOptions& o)
      : chain_(chain), target_(target), o_(o) {}

  void evaluate(const JointVector& q, Error& e, Jacobian& j) const {
    ChainJacobian full;
    const Eigen::Isometry3d tip = chain_.forward(q, full);
    e.template head<3>() = target_.translation() - tip.translation();
    if constexpr (M == 6) {
      // Rotation that takes the tip's orientation to the target's, as an angle-axis vector.
      const Eigen::AngleAxisd r(target_.linear() * tip.linear().transpose());
      e.template tail<3>() = o_.orientation_weight * r.angle() * r.axis();
      j = full;
      j.template bottomRows<3>() *= o_.orientation_weight;
    } else {
      j = full.template topRows<3>();
    }
  }

  double position_error(const Error& e) const { return e.template head<3>().norm(); }
  double orientation_error(const Error& e) const {
    if constexpr (M == 6) return e.template tail<3>().norm() / o_.orientation_weight;
    return 0.0;
  }
  bool done(const Error& e) const {
    return position_error(e) <= o_.tolerance && orientation_error(e) <= o_.orientation_tolerance;
  }

private:
  const KinematicChain& chain_;
  const Eigen::Isometry3d& target_;
  const IkOptions& o_;
};

template <int M>
IkResult solve(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& start,
               const IkOptions& o) {
  using T = Task<M>;
  const T task(chain, target, o);
  constexpr double kMinDamping = 1e-4, kMaxDamping = 1e3;

  IkResult r;
  r.q = chain.clamp(start);
  typename T::Error e, e_new;
  typename T::Jacobian j, j_new;
  task.evaluate(r.q, e, j);
  double cost = e.squaredNorm();
  double damping = o.damping;
  while (r.iterations < o.max_iterations && !task.done(e)) {
    ++r.iterations;
    // Joints at a limit that the step would push further are taken out of the step (their
    // Jacobian columns zeroed) so the others make up for them, instead of the clamp eating the step.
    typename T::Jacobian free = j;
    JointVector dq;
    for (int pass = 0; pass < 3; ++pass) {
      dq = damped_least_squares_step(free, e, damping);
      bool blocked = false;
      for (int i = 0; i < dq.size(); ++i) {
        const bool at_lower = r.q[i] <= chain.lower()[i] && dq[i] < 0.0;
        const bool at_upper = r.q[i] >= chain.upper()[i] && dq[i] > 0.0;
        if ((at_lower || at_upper) && free.col(i).squaredNorm() > 0.0) {
          free.col(i).setZero();
          blocked = true;
        }
      }
      if (!blocked) break;
    }
    double largest = 0.0;  // a plain loop: GCC 12 misreads Eigen's vectorised maxCoeff here (-Wmaybe-uninitialized)
    for (int i = 0; i < dq.size(); ++i) largest = std::max(largest, std::abs(dq[i]));
    if (largest > o.max_joint_step) dq *= o.max_joint_step / largest;
    const JointVector q_new = chain.clamp(r.q + dq);
    task.evaluate(q_new, e_new, j_new);
    const double cost_new = e_new.squaredNorm();
    if (cost_new < cost) {
      r.q = q_new;
      e = e_new;
      j = j_new;
      cost = cost_new;
      damping = std::max(damping * 0.5, kMinDamping);
    } else {
      // Worse (overshoot, or a joint limit in the way): trust the linear model less.
      damping *= 4.0;
      if (damping > kMaxDamping) break;
    }
  }
  r.position_error = task.position_error(e);
  r.orientation_error = task.orientation_error(e);
  r.converged = task.done(e);
  return r;
}

// Local minima exist (joint limits fold the arm the wrong way): retry from fixed pseudo-random
// configurations, so the answer depends only on the inputs.
template <int M>
IkResult solve_with_restarts(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& start,
                             const IkOptions& o) {
  IkResult best = solve<M>(chain, target, start, o);
  Rng rng(0x1C0FFEEull);
  for (int k = 0; k < o.restarts && !best.converged; ++k) {
    JointVector q(chain.dof());
    for (int i = 0; i < chain.dof(); ++i)
      q[i] = rng.uniform(std::max(chain.lower()[i], -M_PI), std::min(chain.upper()[i], M_PI));
    IkResult r = solve<M>(chain, target, q, o);
    r.iterations += best.iterations;
    const bool better = r.converged || r.position_error + r.orientation_error < best.position_error + best.orientation_error;
    if (better) {
      best = r;
    } else {
      best.iterations = r.iterations;
    }
  }
  return best;
}

// (J J^T + damping^2 I)^-1 e for a 3-row J, by a Cholesky factorisation written out (the IK's
// inner loop: Eigen's LLT runs its general loops on a 3x3).
Eigen::Vector3d damped_solve(const PositionJacobian& j, const Eigen::Vector3d& e, double damping) {
  const double d2 = damping * damping;
  const double a00 = j.row(0).squaredNorm() + d2, a11 = j.row(1).squaredNorm() + d2, a22 = j.row(2).squaredNorm() + d2;
  const double a01 = j.row(0).dot(j.row(1)), a02 = j.row(0).dot(j.row(2)), a12 = j.row(1).dot(j.row(2));
  const double l00 = std::sqrt(a00), l10 = a01 / l00, l20 = a02 / l00;
  const double l11 = std::sqrt(a11 - l10 * l10), l21 = (a12 - l20 * l10) / l11;
  const double l22 = std::sqrt(a22 - l20 * l20 - l21 * l21);
  const double z0 = e[0] / l00, z1 = (e[1] - l10 * z0) / l11, z2 = (e[2] - l20 * z0 - l21 * z1) / l22;
  const double y2 = z2 / l22, y1 = (z1 - l21 * y2) / l11;
  return {(z0 - l10 * y1 - l20 * y2) / l00, y1, y2};
}

}  // namespace

JointVector null_space_ik(const KinematicChain& chain, const Eigen::Vector3d& target, const JointVector& start,
                          const JointVector& rest, const NullSpaceIkOptions& o) {
  JointVector q = start;
  double error_norm = std::numeric_limits<double>::infinity();
  // As pybullet: the loop tests the error measured at the start of the previous iteration, so the
  // step that begins within `tolerance` is still taken.
  for (int it = 0; it < o.iterations && error_norm > o.tolerance; ++it) {
    PositionJacobian j;
    const Eigen::Vector3d error = target - chain.tip_position(q, j);
    error_norm = error.norm();
    // The null-space velocity: a pull towards the rest pose, and a push back from beyond a limit of
    // limit_gain x (limit - q) / range (a joint inside its limits feels only the pull).
    JointVector pull = o.rest_gain * (rest - q);
    for (int i = 0; i < q.size(); ++i) {
      const double lo = chain.lower()[i], hi = chain.upper()[i], range = hi - lo;
      if (!std::isfinite(range) || range <= 0.0) continue;
      if (q[i] > hi) pull[i] += o.limit_gain * (hi - q[i]) / range;
      if (q[i] < lo) pull[i] += o.limit_gain * (lo - q[i]) / range;
    }
    // J^T A^-1 e + (I - J^T A^-1 J) p  =  J^T A^-1 (e - J p) + p,  A = J J^T + damping^2 I: the DLS
    // step towards what the pull p leaves of the error, plus the pull.
    // (Column by column: Eigen's general matrix-vector kernels cost more than a 3 x 6 product.)
    Eigen::Vector3d rest_error = error;
    for (int i = 0; i < q.size(); ++i) rest_error -= j.col(i) * pull[i];
    const Eigen::Vector3d y = damped_solve(j, rest_error, o.damping);
    JointVector dq(q.size());
    double largest = 0.0;  // a plain loop, as in solve() (GCC 12 and Eigen's maxCoeff)
    for (int i = 0; i < q.size(); ++i) {
      dq[i] = j.col(i).dot(y) + pull[i];
      largest = std::max(largest, std::abs(dq[i]));
    }
    if (largest > o.max_joint_step) dq *= o.max_joint_step / largest;
    q += dq;
  }
  return q;
}

IkResult solve_ik(const KinematicChain& chain, const Eigen::Vector3d& target, const JointVector& start,
                  const IkOptions& options) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = target;
  return solve_with_restarts<3>(chain, pose, start, options);
}

IkResult solve_ik(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& start,
                  const IkOptions& options) {
  return solve_with_restarts<6>(chain, target, start, options);
}

}  // namespace rdsim
