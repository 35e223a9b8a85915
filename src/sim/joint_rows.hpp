#pragma once
// Bullet's joint motor, joint limit and gear (btMultiBodyJointMotor, btMultiBodyJointLimitConstraint,
// btMultiBodyGearConstraint) with their solver rows set up without the work that yields zeros;
// only src/sim includes this.
//
// Why: both constraints name their multibody twice, as body A and body B, and Bullet computes
// each row's unit-impulse response for both sides, one articulated-body pass each
// (btMultiBody::calcAccelerationDeltasMultiDof), though one side's Jacobian is all zeros and so
// is its response (a motor's B side; a limit's B side on its lower row, A side on its upper row).
// With a position motor on every joint that was the largest single cost of the paper presets'
// physics step (about a sixth of it for the Jaka arm).
//
// Exact: a row gets what Bullet's constraint and btMultiBodyConstraint::fillMultiBodyConstraint
// give it, field for field and rounded as they round (this file is compiled without
// floating-point contraction, as Bullet is): the same Jacobians, a side's response from the same
// Bullet call or left at the zeros its storage starts with when its Jacobian is all zeros, and
// the sums over both sides in Bullet's order (adding exact zeros changes no sum). tests/sim: a
// world with these constraints steps bit for bit as one with Bullet's
// (WorldSettings::sparse_joint_rows). Not so when the robot hands its rows JointResponses (below).
#include <BulletDynamics/Featherstone/btMultiBodyGearConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>

#include <Eigen/Core>
#include <vector>

namespace rdsim {

// A robot's joint-space response to a unit impulse on each joint, M(q)^-1 from rdsim's own mass
// matrix (composite rigid bodies, double precision), computed by the robot before each physics
// step (WorldSettings::mass_matrix_responses). A joint row whose Jacobian is one joint's takes its
// response from here instead of a Bullet articulated-body pass of its own: one factorisation per
// step against one pass per row. Not bit-exact: Bullet computes the passes in single precision.
// Only the columns the step's rows ask for are solved (a gripper's fingers: 2 of 8).
class JointResponses {
public:
  bool valid = false;                // false: the rows use Bullet's passes (e.g. joints welded)
  std::vector<int> velocity_index;   // per dof: its entry in Bullet's velocity vector (6 + dof offset)

  // A new step's M(q) (the robot's dof order): factorised here; false (and not valid) when it is not
  // positive definite.
  bool set_mass(const Eigen::MatrixXd& mass);
  // Column `dof` of M^-1, solved on its first use this step; nullptr when it is not finite.
  const double* column(int dof) const;

private:
  Eigen::MatrixXd factor_;            // cholesky()'s L of M = L L^T
  mutable Eigen::MatrixXd columns_;   // M^-1's columns solved so far this step
  mutable std::vector<signed char> solved_;  // per column: 0 not yet, 1 finite, -1 not finite
};

// Where a joint row takes its responses from: column `dof` of `responses` (kept by the robot,
// which outlives its rows), or Bullet's passes while there is none.
struct ResponseSource {
  const JointResponses* responses = nullptr;
  int dof = -1;
};

// A joint motor on a one-degree-of-freedom joint (Bullet's motor law and row).
class JointMotor : public btMultiBodyJointMotor {
public:
  JointMotor(btMultiBody* body, int link, btScalar max_impulse) : btMultiBodyJointMotor(body, link, 0, 0, max_impulse) {}

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void use_responses(const ResponseSource& source) { source_ = source; }

private:
  btScalar target_velocity(const btContactSolverInfo& info) const;  // rad/s or m/s
  ResponseSource source_;
};

// The two rows of a joint's limits, each present only while the joint is at or past that limit.
class JointLimit : public btMultiBodyJointLimitConstraint {
public:
  JointLimit(btMultiBody* body, int link, btScalar lower, btScalar upper)
      : btMultiBodyJointLimitConstraint(body, link, lower, upper) {}

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void use_responses(const ResponseSource& source) { source_ = source; }

private:
  ResponseSource source_;
};

// Bullet's gear between two one-degree-of-freedom joints of one multibody: q_a + ratio q_b held at
// the relative target (with ratio -1 the two joints equal), erp of the error corrected per step, the
// row's impulse within +-max. Its Jacobian has one joint's entry on each side, so with JointResponses
// each side's response is that joint's column of M^-1 (two Bullet passes per step without).
class JointGear : public btMultiBodyGearConstraint {
public:
  JointGear(btMultiBody* body, int link_a, int link_b);

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void use_responses(const ResponseSource& a, const ResponseSource& b) {
    source_a_ = a;
    source_b_ = b;
  }

private:
  ResponseSource source_a_, source_b_;
};

}  // namespace rdsim
