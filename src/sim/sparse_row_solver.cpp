#include "sparse_row_solver.hpp"

#include "small_cholesky.hpp"

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <algorithm>
#include <cmath>

namespace rdsim {

btScalar SparseRowSolver::solveGroupCacheFriendlySetup(btCollisionObject** bodies, int numBodies,
                                                        btPersistentManifold** manifolds, int numManifolds,
                                                        btTypedConstraint** constraints, int numConstraints,
                                                        const btContactSolverInfo& info, btIDebugDraw* debugDrawer) {
  const btScalar r = btMultiBodyConstraintSolver::solveGroupCacheFriendlySetup(
      bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer);
  list_rows();
  if (warm_start_ != 0) warm_start_rows();
  if (block_solve_) block_solve_rows();
  return r;
}

void SparseRowSolver::apply_impulse(const Side& side, btScalar impulse) {
  if (!side.responds) return;  // adding zeros
  const btScalar* response = &m_data.m_deltaVelocitiesUnitImpulse[side.jacobian];
  btScalar* v = &m_data.m_deltaVelocities[side.velocity];
  for (int i = 0; i < side.size; ++i) v[i] += response[i] * impulse;
  side.body->applyDeltaVeeMultiDof2(response, impulse);
}

std::array<int, 4> SparseRowSolver::row_key(const btMultiBodySolverConstraint& c) {
  btMultiBodyConstraint& constraint = *c.m_orgConstraint;
  const btMultiBody* body = constraint.getMultiBodyA();
  return {body ? body->getUserIndex() : -1, constraint.getLinkA(), constraint.getConstraintType(), c.m_orgDofIndex};
}

void SparseRowSolver::warm_start_rows() {
  for (int k = 0; k < m_multiBodyNonContactConstraints.size(); ++k) {
    btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[k];
    const Row& row = rows_[static_cast<size_t>(k)];
    if (!c.m_orgConstraint || !row.a.body || !row.b.body) continue;
    const Impulse key{row_key(c), 0};
    const auto it = std::lower_bound(last_.begin(), last_.end(), key);
    if (it == last_.end() || it->key != key.key) continue;
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
      if (c.m_orgConstraint) last_.push_back({row_key(c), c.m_appliedImpulse});
    }
    std::sort(last_.begin(), last_.end());
  }
  return btMultiBodyConstraintSolver::solveGroupCacheFriendlyFinish(bodies, numBodies, info);
}

// The joint rows' fixed point, found directly. Row i is at rest in solve_row when
//   rhs_i - cfm_i x_i - jdi_i J_i . dv(x) = 0,   dv(x) = dv_now + sum_j r_j (x_j - x_now_j),
// with J_i its Jacobian and r_j row j's unit-impulse response, each the sum of the row's A and
// B sides (both on this multibody: a joint limit's upper row is written on its B side), and jdi_i
// its m_jacDiagABInv. Divided by jdi_i:
//   K x = b,   K = A + diag(cfm / jdi),   A_ij = J_i . r_j (J M^-1 J^T: symmetric),
//   b_i = rhs_i / jdi_i - J_i . dv_now + (A x_now)_i,
// each x_i within [lower_i, upper_i]: a row at a bound stays there while the others want it
// pushed further (active-set rounds of an LDLT solve).
void SparseRowSolver::block_solve_rows() {
  const int n = m_multiBodyNonContactConstraints.size();
  if (n == 0 || n > kMaxBlockRows || static_cast<int>(rows_.size()) != n) return;
  const btMultiBody* body = rows_[0].a.body;
  for (const Row& row : rows_)  // one multibody's own rows only
    if (!body || row.a.body != body || (row.b.body && (row.b.body != body || row.b.velocity != row.a.velocity))) return;
  Block& k = block_;
  k.matrix.resize(n, n);
  k.rhs.resize(n);
  k.x.resize(n);
  k.state.assign(static_cast<size_t>(n), 0);
  const btScalar* jacobians = &m_data.m_jacobians[0];
  const btScalar* responses = &m_data.m_deltaVelocitiesUnitImpulse[0];
  const btScalar* dv = &m_data.m_deltaVelocities[0] + rows_[0].a.velocity;
  // J_i . v for a vector v over this body's velocities, both sides of row i.
  auto dot = [&](const Row& row, auto&& v) {
    double sum = 0;
    for (const Side* s : {&row.a, &row.b})
      if (s->body)
        for (int e = s->begin; e < s->end; ++e) sum += double(jacobians[s->jacobian + entries_[e]]) * v(entries_[e]);
    return sum;
  };
  for (int i = 0; i < n; ++i) {
    const btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[i];
    const Row& row = rows_[static_cast<size_t>(i)];
    const double jdi = c.m_jacDiagABInv;
    if (!(jdi > 0)) return;
    for (int j = 0; j < n; ++j) {
      const Row& other = rows_[static_cast<size_t>(j)];
      k.matrix(i, j) = dot(row, [&](int e) {
        double r = other.a.responds ? responses[other.a.jacobian + e] : 0.0;
        if (other.b.responds) r += responses[other.b.jacobian + e];
        return r;
      });
    }
    k.rhs(i) = double(c.m_rhs) / jdi - dot(row, [&](int e) { return double(dv[e]); });
    k.x(i) = c.m_appliedImpulse;
  }
  k.rhs += k.matrix * k.x;
  for (int i = 0; i < n; ++i) {
    const btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[i];
    k.matrix(i, i) += double(c.m_cfm) / c.m_jacDiagABInv;
  }
  if (!solve_block(n)) return;  // Bullet's iterations alone, from where the rows are
  for (int i = 0; i < n; ++i) {
    btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[i];
    const btScalar impulse = std::clamp(static_cast<btScalar>(k.x(i)), c.m_lowerLimit, c.m_upperLimit);
    const btScalar delta = impulse - btScalar(c.m_appliedImpulse);
    c.m_appliedImpulse = impulse;
    apply_impulse(rows_[static_cast<size_t>(i)].a, delta);
    apply_impulse(rows_[static_cast<size_t>(i)].b, delta);
  }
}

// Cholesky factor of a free block (symmetric positive definite: J M^-1 J^T plus the rows' CFM).
// Dependent rows (a motor and a limit row on one joint, both free) make it singular: they ask one
// velocity for two values, and the answer is one of them at its bound. A diagonal of 1e-9 of the
// largest entry lets the solve say which: it sends the pair's impulses far apart, past their
// bounds, and the next active-set round clamps them.
bool SparseRowSolver::factor(BlockMatrix& sub) {
  const int m = static_cast<int>(sub.rows());
  Block& k = block_;
  k.factor = sub;
  if (cholesky(k.factor, m)) return true;
  k.factor = sub;
  k.factor.diagonal().array() += 1e-9 * sub.diagonal().cwiseAbs().maxCoeff();
  return cholesky(k.factor, m);
}

// The active-set rounds of block_solve_rows on block_; false when they find no answer.
bool SparseRowSolver::solve_block(int n) {
  Block& k = block_;
  for (int round = 0; round < 2 * n + 2; ++round) {
    k.free.clear();
    for (int i = 0; i < n; ++i) {
      const btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[i];
      if (k.state[static_cast<size_t>(i)] == 0) k.free.push_back(i);
      else k.x(i) = k.state[static_cast<size_t>(i)] < 0 ? c.m_lowerLimit : c.m_upperLimit;
    }
    const int m = static_cast<int>(k.free.size());
    if (m > 0) {
      k.sub.resize(m, m);
      k.sub_rhs.resize(m);
      for (int p = 0; p < m; ++p) {
        const int i = k.free[static_cast<size_t>(p)];
        k.sub_rhs(p) = k.rhs(i);
        for (int j = 0; j < n; ++j)
          if (k.state[static_cast<size_t>(j)] != 0) k.sub_rhs(p) -= k.matrix(i, j) * k.x(j);
        for (int q = 0; q < m; ++q) k.sub(p, q) = k.matrix(i, k.free[static_cast<size_t>(q)]);
      }
      if (!factor(k.sub)) return false;
      cholesky_solve(k.factor, m, k.sub_rhs);
      for (int p = 0; p < m; ++p) k.x(k.free[static_cast<size_t>(p)]) = k.sub_rhs(p);
    }
    if (!k.x.allFinite()) return false;
    bool settled = true;
    for (int i = 0; i < n; ++i) {
      const btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[i];
      int& state = k.state[static_cast<size_t>(i)];
      const double wants = k.rhs(i) - k.matrix.row(i).dot(k.x);  // > 0: the row wants more impulse
      const int next = state == 0 ? (k.x(i) < c.m_lowerLimit ? -1 : k.x(i) > c.m_upperLimit ? 1 : 0)
                                  : ((state < 0 && wants > 0) || (state > 0 && wants < 0) ? 0 : state);
      settled &= next == state;
      state = next;
    }
    if (settled) return true;
  }
  return false;
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
  ++iterations_;
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
