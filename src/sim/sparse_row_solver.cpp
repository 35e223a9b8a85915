#include "sparse_row_solver.hpp"

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <algorithm>

namespace rdsim {

btScalar SparseRowSolver::solveGroupCacheFriendlySetup(btCollisionObject** bodies, int numBodies,
                                                        btPersistentManifold** manifolds, int numManifolds,
                                                        btTypedConstraint** constraints, int numConstraints,
                                                        const btContactSolverInfo& info, btIDebugDraw* debugDrawer) {
  const btScalar r = btMultiBodyConstraintSolver::solveGroupCacheFriendlySetup(
      bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer);
  list_rows();
  if (warm_start_ != 0) warm_start_rows();
  return r;
}

void SparseRowSolver::apply_impulse(const Side& side, btScalar impulse) {
  if (!side.responds) return;  // adding zeros
  const btScalar* response = &m_data.m_deltaVelocitiesUnitImpulse[side.jacobian];
  btScalar* v = &m_data.m_deltaVelocities[side.velocity];
  for (int i = 0; i < side.size; ++i) v[i] += response[i] * impulse;
  side.body->applyDeltaVeeMultiDof2(response, impulse);
}

void SparseRowSolver::warm_start_rows() {
  for (int k = 0; k < m_multiBodyNonContactConstraints.size(); ++k) {
    btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[k];
    const Row& row = rows_[static_cast<size_t>(k)];
    if (!c.m_orgConstraint || !row.a.body || !row.b.body) continue;
    const Impulse key{c.m_orgConstraint, c.m_orgDofIndex, 0};
    const auto it = std::lower_bound(last_.begin(), last_.end(), key);
    if (it == last_.end() || it->constraint != key.constraint || it->row != key.row) continue;
    const btScalar impulse = std::clamp(warm_start_ * it->impulse, c.m_lowerLimit, c.m_upperLimit);
    if (impulse == 0) continue;
    c.m_appliedImpulse = impulse;
    apply_impulse(row.a, impulse);
    apply_impulse(row.b, impulse);
  }
}

btScalar SparseRowSolver::solveGroupCacheFriendlyFinish(btCollisionObject** bodies, int numBodies,
                                                         const btContactSolverInfo& info) {
  last_.clear();
  if (warm_start_ != 0) {
    for (int k = 0; k < m_multiBodyNonContactConstraints.size(); ++k) {
      const btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[k];
      if (c.m_orgConstraint) last_.push_back({c.m_orgConstraint, c.m_orgDofIndex, c.m_appliedImpulse});
    }
    std::sort(last_.begin(), last_.end());
  }
  return btMultiBodyConstraintSolver::solveGroupCacheFriendlyFinish(bodies, numBodies, info);
}

SparseRowSolver::Side SparseRowSolver::list_side(btMultiBody* body, int jacobian, int velocity) {
  Side s;
  if (!body) return s;  // a rigid body or nothing on this side: Bullet's own row code (solve_row)
  s.body = body;
  s.jacobian = jacobian;
  s.velocity = velocity;
  s.size = body->getNumDofs() + 6;
  s.begin = static_cast<int>(entries_.size());
  for (int i = 0; i < s.size; ++i) {
    if (m_data.m_jacobians[jacobian + i] != btScalar(0)) entries_.push_back(i);
    s.responds |= m_data.m_deltaVelocitiesUnitImpulse[jacobian + i] != btScalar(0);
  }
  s.end = static_cast<int>(entries_.size());
  return s;
}

void SparseRowSolver::list_rows() {
  rows_.clear();
  entries_.clear();
  for (int k = 0; k < m_multiBodyNonContactConstraints.size(); ++k) {
    const btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[k];
    Row row;
    row.a = list_side(c.m_multiBodyA, c.m_jacAindex, c.m_deltaVelAindex);
    row.b = list_side(c.m_multiBodyB, c.m_jacBindex, c.m_deltaVelBindex);
    rows_.push_back(row);
  }
}

// btMultiBodyConstraintSolver::resolveSingleConstraintRowGeneric for a row between multibodies,
// term for term (Bullet's build updates the solver's velocities and the multibody's pending
// velocity change, DIRECTLY_UPDATE_VELOCITY_DURING_SOLVER_ITERATIONS).
btScalar SparseRowSolver::solve_row(btMultiBodySolverConstraint& c, const Row& row) {
  if (!row.a.body || !row.b.body) return resolveSingleConstraintRowGeneric(c);
  const btScalar* jacobians = &m_data.m_jacobians[0];
  btScalar* velocities = &m_data.m_deltaVelocities[0];
  const int* entries = entries_.data();
  auto dot = [&](const Side& s) {
    btScalar sum = 0;
    for (int e = s.begin; e < s.end; ++e) sum += jacobians[s.jacobian + entries[e]] * velocities[s.velocity + entries[e]];
    return sum;
  };
  btScalar delta = c.m_rhs - btScalar(c.m_appliedImpulse) * c.m_cfm;
  const btScalar dot_a = dot(row.a);
  const btScalar dot_b = dot(row.b);
  delta -= dot_a * c.m_jacDiagABInv;
  delta -= dot_b * c.m_jacDiagABInv;
  const btScalar sum = btScalar(c.m_appliedImpulse) + delta;
  if (sum < c.m_lowerLimit) {
    delta = c.m_lowerLimit - c.m_appliedImpulse;
    c.m_appliedImpulse = c.m_lowerLimit;
  } else if (sum > c.m_upperLimit) {
    delta = c.m_upperLimit - c.m_appliedImpulse;
    c.m_appliedImpulse = c.m_upperLimit;
  } else {
    c.m_appliedImpulse = sum;
  }
  apply_impulse(row.a, delta);
  apply_impulse(row.b, delta);
  return delta / c.m_jacDiagABInv;  // the row's velocity residual, as Bullet reports it
}

btScalar SparseRowSolver::solveSingleIteration(int iteration, btCollisionObject** bodies, int numBodies,
                                               btPersistentManifold** manifolds, int numManifolds,
                                               btTypedConstraint** constraints, int numConstraints,
                                               const btContactSolverInfo& info, btIDebugDraw* debugDrawer) {
  const int n = m_multiBodyNonContactConstraints.size();
  if (!sparse_ || n == 0 || static_cast<int>(rows_.size()) != n)
    return btMultiBodyConstraintSolver::solveSingleIteration(iteration, bodies, numBodies, manifolds, numManifolds,
                                                             constraints, numConstraints, info, debugDrawer);
  // Bullet's order: rigid-body rows (rdsim has none: its only rigid objects are static), then the
  // joint rows (forwards on odd iterations, backwards on even ones), then the contacts. The joint
  // rows are solved here and hidden from Bullet's pass, which does the rest.
  btScalar joint_residual = 0;
  for (int inner = 0; inner < info.m_numNonContactInnerIterations; ++inner) {
    joint_residual = 0;
    for (int j = 0; j < n; ++j) {
      const int index = iteration & 1 ? j : n - 1 - j;
      btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[index];
      const btScalar r = solve_row(c, rows_[static_cast<size_t>(index)]);
      joint_residual = std::max(joint_residual, r * r);
      if (c.m_multiBodyA) c.m_multiBodyA->setPosUpdated(false);
      if (c.m_multiBodyB) c.m_multiBodyB->setPosUpdated(false);
    }
  }
  m_multiBodyNonContactConstraints.resizeNoInitialize(0);  // keeps the rows' storage
  const btScalar rest = btMultiBodyConstraintSolver::solveSingleIteration(
      iteration, bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer);
  m_multiBodyNonContactConstraints.resizeNoInitialize(n);
  return std::max(joint_residual, rest);  // Bullet takes the largest squared residual of all rows
}

}  // namespace rdsim
