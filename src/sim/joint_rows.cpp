#include "joint_rows.hpp"

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include "small_cholesky.hpp"

namespace rdsim {
namespace {

// One side of a row: its Jacobian's and response's slot in the solver's arrays (Jacobian copied
// from `jacobian`), and its multibody's slot in the solver's velocity changes. The response is
// left at zero, as the arrays grow, when the Jacobian is all zeros: M^-1 0 = 0.
struct SideSlots {
  int jacobian = 0, velocity = 0;
};

SideSlots add_side(btMultiBody* body, const btScalar* jacobian, btMultiBodyJacobianData& data,
                   const ResponseSource& source) {
  const int n = body->getNumDofs() + 6;
  SideSlots s;
  s.velocity = body->getCompanionId();
  if (s.velocity < 0) {  // the body's first row this solve: its velocity changes get a slot
    s.velocity = data.m_deltaVelocities.size();
    body->setCompanionId(s.velocity);
    data.m_deltaVelocities.resize(data.m_deltaVelocities.size() + n);
  }
  s.jacobian = data.m_jacobians.size();
  data.m_jacobians.resize(data.m_jacobians.size() + n);
  data.m_deltaVelocitiesUnitImpulse.resize(data.m_deltaVelocitiesUnitImpulse.size() + n);  // zeros
  bool zero = true;
  for (int i = 0; i < n; ++i) {
    data.m_jacobians[s.jacobian + i] = jacobian[i];
    zero &= jacobian[i] == btScalar(0);
  }
  if (zero) return s;
  btScalar* response = &data.m_deltaVelocitiesUnitImpulse[s.jacobian];
  const JointResponses* r = source.responses;
  if (r && r->valid && source.dof >= 0 && static_cast<int>(r->velocity_index.size()) == n - 6) {
    // A Jacobian of one joint's entry alone (a motor's or limit's side): that entry times the
    // joint's column of M^-1; the fixed base does not move.
    const int own = r->velocity_index[static_cast<size_t>(source.dof)];
    bool one_joint = true;
    for (int i = 0; i < n; ++i) one_joint &= i == own || jacobian[i] == btScalar(0);
    const double* column = one_joint ? r->column(source.dof) : nullptr;
    if (column) {
      const double value = jacobian[own];
      for (int j = 0; j < n - 6; ++j)
        response[r->velocity_index[static_cast<size_t>(j)]] = static_cast<btScalar>(value * column[j]);
      return s;
    }
  }
  body->calcAccelerationDeltasMultiDof(&data.m_jacobians[s.jacobian], response, data.scratch_r, data.scratch_v);
  return s;
}

// sum_i a[i] b[i] added to `sum` in Bullet's order.
btScalar add_dot(btScalar sum, const btScalar* a, const btScalar* b, int n) {
  for (int i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

// What fillMultiBodyConstraint does for a joint row (one degree of freedom, both sides
// multibodies, no position error): Jacobians and responses, the effective mass 1 / (J M^-1 J^T)
// (0 for a row nothing responds to), bounds, and a right-hand side that asks for
// `desired_velocity`. Returns the row's velocity J v. Each side's response from its source when
// that has them.
btScalar fill_joint_row(btMultiBodySolverConstraint& c, btMultiBodyJacobianData& data, const btScalar* jacobian_a,
                        const btScalar* jacobian_b, btScalar lower, btScalar upper, btScalar desired_velocity,
                        const ResponseSource& source_a, const ResponseSource& source_b) {
  btMultiBody* body_a = c.m_multiBodyA;
  btMultiBody* body_b = c.m_multiBodyB;
  const int na = body_a->getNumDofs() + 6, nb = body_b->getNumDofs() + 6;
  const SideSlots a = add_side(body_a, jacobian_a, data, source_a);
  const SideSlots b = add_side(body_b, jacobian_b, data, source_b);
  c.m_deltaVelAindex = a.velocity;
  c.m_jacAindex = a.jacobian;
  c.m_deltaVelBindex = b.velocity;
  c.m_jacBindex = b.jacobian;

  const btScalar* jacobians = &data.m_jacobians[0];
  const btScalar* responses = &data.m_deltaVelocitiesUnitImpulse[0];
  const btScalar denom_a = add_dot(0, jacobians + a.jacobian, responses + a.jacobian, na);
  const btScalar denom_b = add_dot(0, jacobians + b.jacobian, responses + b.jacobian, nb);
  const btScalar d = denom_a + denom_b;
  c.m_jacDiagABInv = d > SIMD_EPSILON ? btScalar(1) / d : btScalar(0);

  // One sum from 0 over A's products, then B's (Bullet multiplies velocity by Jacobian).
  btScalar velocity = add_dot(0, body_a->getVelocityVector(), jacobians + a.jacobian, na);
  velocity = add_dot(velocity, body_b->getVelocityVector(), jacobians + b.jacobian, nb);

  c.m_friction = 0;
  c.m_appliedImpulse = 0;
  c.m_appliedPushImpulse = 0;
  // Bullet adds a positional term of -0 (no position error) to the velocity term: x + -0 = x.
  c.m_rhs = (desired_velocity - velocity) * c.m_jacDiagABInv;
  c.m_rhsPenetration = 0;
  c.m_cfm = 0;
  c.m_lowerLimit = lower;
  c.m_upperLimit = upper;
  return velocity;
}

// A row's right-hand side as Bullet's fillMultiBodyConstraint makes it from the row's position
// error `penetration` and its velocity impulse: erp of the error per step, combined with the
// velocity term, or kept apart for the split-impulse push when split impulses are on.
void add_position_error(btMultiBodySolverConstraint& c, const btContactSolverInfo& info, btScalar penetration,
                        btScalar velocity_impulse) {
  const bool combined = !info.m_splitImpulse || penetration > info.m_splitImpulsePenetrationThreshold;
  const btScalar erp = combined ? info.m_erp : info.m_erp2;
  const btScalar positional = -penetration * erp / info.m_timeStep;
  const btScalar penetration_impulse = positional * c.m_jacDiagABInv;
  c.m_rhs = combined ? penetration_impulse + velocity_impulse : velocity_impulse;
  c.m_rhsPenetration = combined ? btScalar(0) : penetration_impulse;
}

// The joint's axis in the world, times `direction`, where Bullet records it on a joint row (its
// joint-force feedback reads it).
void record_axis(btMultiBodySolverConstraint& c, const btMultibodyLink& link, btScalar direction) {
  const btQuaternion rotation = link.m_cachedWorldTransform.getRotation();
  if (link.m_jointType == btMultibodyLink::eRevolute) {
    const btVector3 axis = direction * quatRotate(rotation, link.m_axes[0].m_topVec);
    c.m_contactNormal1.setZero();
    c.m_contactNormal2.setZero();
    c.m_relpos1CrossNormal = axis;
    c.m_relpos2CrossNormal = -axis;
  } else {
    const btVector3 axis = direction * quatRotate(rotation, link.m_axes[0].m_bottomVec);
    c.m_contactNormal1 = axis;
    c.m_contactNormal2 = -axis;
    c.m_relpos1CrossNormal.setZero();
    c.m_relpos2CrossNormal.setZero();
  }
}

// rdsim's joint rows: a revolute or prismatic joint, both sides on one multibody. Anything else
// goes through Bullet's own row code.
bool supported(const btMultiBody* a, const btMultiBody* b, int link) {
  const int type = a->getLink(link).m_jointType;
  return b == a && (type == btMultibodyLink::eRevolute || type == btMultibodyLink::ePrismatic);
}

}  // namespace

bool JointResponses::set_mass(const Eigen::MatrixXd& mass) {
  const int n = static_cast<int>(mass.rows());
  factor_ = mass;
  columns_.resize(n, n);
  solved_.assign(static_cast<size_t>(n), 0);
  valid = cholesky(factor_, n);  // M = L L^T, in place
  return valid;
}

const double* JointResponses::column(int dof) const {
  signed char& state = solved_[static_cast<size_t>(dof)];
  if (state == 0) {
    auto x = columns_.col(dof);
    x.setZero();
    x[dof] = 1.0;
    cholesky_solve(factor_, static_cast<int>(factor_.rows()), x);
    state = x.allFinite() ? 1 : -1;
  }
  return state > 0 ? columns_.col(dof).data() : nullptr;
}

btScalar JointMotor::target_velocity(const btContactSolverInfo& info) const {
  const btScalar position = m_bodyA->getJointPosMultiDof(m_linkA)[0];
  const btScalar velocity = m_bodyA->getJointVelMultiDof(m_linkA)[0];
  const btScalar position_term = m_erp * (m_desiredPosition - position) / info.m_timeStep;
  const btScalar velocity_error = m_desiredVelocity - velocity;
  btScalar rhs = m_kp * position_term + velocity + m_kd * velocity_error;
  if (rhs > m_rhsClamp) rhs = m_rhsClamp;
  if (rhs < -m_rhsClamp) rhs = -m_rhsClamp;
  return rhs;
}

void JointMotor::createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                                      const btContactSolverInfo& info) {
  if (!supported(m_bodyA, m_bodyB, m_linkA) || getNumRows() != 1) {
    btMultiBodyJointMotor::createConstraintRows(rows, data, info);
    return;
  }
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  if (m_numDofsFinalized != m_jacSizeBoth || m_maxAppliedImpulse == btScalar(0)) return;
  btMultiBodySolverConstraint& c = rows.expandNonInitializing();
  c.m_multiBodyA = m_bodyA;
  c.m_multiBodyB = m_bodyB;
  c.m_linkA = m_linkA;
  c.m_linkB = m_linkB;
  fill_joint_row(c, data, jacobianA(0), jacobianB(0), -m_maxAppliedImpulse, m_maxAppliedImpulse, target_velocity(info),
                 source_, source_);
  c.m_orgConstraint = this;
  c.m_orgDofIndex = 0;
  record_axis(c, m_bodyA->getLink(m_linkA), 1);
}

void JointLimit::createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                                      const btContactSolverInfo& info) {
  if (!supported(m_bodyA, m_bodyB, m_linkA)) {
    btMultiBodyJointLimitConstraint::createConstraintRows(rows, data, info);
    return;
  }
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  setPosition(0, m_bodyA->getJointPos(m_linkA) - m_lowerBound);  // how far inside each limit
  setPosition(1, m_upperBound - m_bodyA->getJointPos(m_linkA));
  for (int row = 0; row < 2; ++row) {
    const btScalar penetration = getPosition(row);
    if (penetration > 0) continue;  // inside this limit: no row
    btMultiBodySolverConstraint& c = rows.expandNonInitializing();
    c.m_orgConstraint = this;
    c.m_orgDofIndex = row;
    c.m_multiBodyA = m_bodyA;
    c.m_multiBodyB = m_bodyB;
    c.m_linkA = m_linkA;
    c.m_linkB = m_linkB;
    const btScalar velocity =
        fill_joint_row(c, data, jacobianA(row), jacobianB(row), 0, m_maxAppliedImpulse, 0, source_, source_);
    record_axis(c, m_bodyA->getLink(m_linkA), row ? btScalar(-1) : btScalar(1));
    // Bullet's limit law: stop the joint's motion into the limit and push back erp of the
    // penetration per step.
    add_position_error(c, info, penetration, -velocity * c.m_jacDiagABInv);
  }
}

JointGear::JointGear(btMultiBody* body, int link_a, int link_b)
    : btMultiBodyGearConstraint(body, link_a, body, link_b, btVector3(0, 0, 0), btVector3(0, 0, 0),
                                btMatrix3x3::getIdentity(), btMatrix3x3::getIdentity()) {}

void JointGear::createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                                     const btContactSolverInfo& info) {
  if (!supported(m_bodyA, m_bodyB, m_linkA) || !supported(m_bodyA, m_bodyB, m_linkB) || m_gearAuxLink >= 0 ||
      getNumRows() != 1) {
    btMultiBodyGearConstraint::createConstraintRows(rows, data, info);
    return;
  }
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  if (m_numDofsFinalized != m_jacSizeBoth || m_maxAppliedImpulse == btScalar(0)) return;
  jacobianA(0)[6 + m_bodyA->getLink(m_linkA).m_dofOffset] = 1;
  jacobianB(0)[6 + m_bodyB->getLink(m_linkB).m_dofOffset] = m_gearRatio;
  btMultiBodySolverConstraint& c = rows.expandNonInitializing();
  c.m_multiBodyA = m_bodyA;
  c.m_multiBodyB = m_bodyB;
  c.m_linkA = m_linkA;
  c.m_linkB = m_linkB;
  const btScalar velocity = fill_joint_row(c, data, jacobianA(0), jacobianB(0), -m_maxAppliedImpulse,
                                           m_maxAppliedImpulse, 0, source_a_, source_b_);
  c.m_orgConstraint = this;
  c.m_orgDofIndex = 0;
  record_axis(c, m_bodyA->getLink(m_linkA), 1);
  // Bullet's gear law: the error of q_a + ratio q_b from the target, erp of it (and the solver's
  // erp of that) pushed back per step.
  btScalar error = 0;
  if (m_erp != 0) {
    const btScalar diff = m_gearRatio * m_bodyA->getJointPosMultiDof(m_linkB)[0] + m_bodyA->getJointPosMultiDof(m_linkA)[0];
    error = -m_erp * (m_relativePositionTarget - diff);
  }
  add_position_error(c, info, error, (btScalar(0) - velocity) * c.m_jacDiagABInv);
}

}  // namespace rdsim
