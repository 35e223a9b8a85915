#pragma once
// Bullet's joint motor and joint limit (btMultiBodyJointMotor, btMultiBodyJointLimitConstraint)
// with their solver rows set up without the work that yields zeros; only src/sim includes this.
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
// (WorldSettings::sparse_joint_rows).
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>

namespace rdsim {

// A joint motor on a one-degree-of-freedom joint (Bullet's motor law and row).
class JointMotor : public btMultiBodyJointMotor {
public:
  JointMotor(btMultiBody* body, int link, btScalar max_impulse) : btMultiBodyJointMotor(body, link, 0, 0, max_impulse) {}

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;

private:
  btScalar target_velocity(const btContactSolverInfo& info) const;  // rad/s or m/s
};

// The two rows of a joint's limits, each present only while the joint is at or past that limit.
class JointLimit : public btMultiBodyJointLimitConstraint {
public:
  JointLimit(btMultiBody* body, int link, btScalar lower, btScalar upper)
      : btMultiBodyJointLimitConstraint(body, link, lower, upper) {}

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
};

}  // namespace rdsim
