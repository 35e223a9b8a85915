#pragma once
// Bullet's multibody sequential-impulse solver with its joint rows (motors, joint limits) solved
// on their non-zero entries only; only src/sim includes this.
//
// Why: Bullet solves every row over all of its multibody's velocities, twice (body A and body B)
// and on every iteration: a joint motor's row is a dot product and an update over 6 + dofs
// numbers for each side, though its Jacobian has a single non-zero entry and its B side is all
// zeros (a joint motor names the same multibody twice). With the paper presets' 150 iterations
// and a motor on each of the InMoov's 54 joints that was most of a physics step.
//
// Exact: after Bullet's own setup the non-zero entries of each row's Jacobian are listed once per
// step; each iteration then does Bullet's arithmetic in Bullet's order: the dot products over the
// listed entries (skipping a product with an exact zero changes no sum: x + 0 = x), the velocity
// updates element by element as Bullet does them, vectorised, and not at all for a side whose
// response is all zeros. The solver's impulses and the step's velocities are the same bits
// (tests/sim: sparse and dense worlds step identically). This file is compiled without
// floating-point contraction, as Bullet is, so that a*b+c is never fused into one rounding where
// Bullet rounds twice.
// Contact rows go through Bullet's own code unchanged (their Jacobians are dense along the path
// to the root, and they are few).
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace rdsim {

class SparseRowSolver : public btMultiBodyConstraintSolver {
public:
  // false: Bullet's dense rows (the reference the tests compare with).
  void set_sparse(bool sparse) { sparse_ = sparse; }
  // Each joint row starts from `factor` times the impulse it ended the last step with (0: from
  // zero, as Bullet does). See WorldSettings::joint_row_warm_start.
  void set_warm_start(double factor) { warm_start_ = static_cast<btScalar>(factor); }
  // Before the iterations, solve one multibody's joint rows together, directly (see
  // WorldSettings::joint_block_solve).
  void set_block_solve(bool on) { block_solve_ = on; }
  long long iterations() const { return iterations_; }  // solveSingleIteration calls so far
  // Drops the joint rows' impulses kept for the next step's warm start (a cache, like Bullet's
  // contact manifolds: PhysicsWorld::forget_all_contacts).
  void forget_warm_starts() { last_.clear(); }

  btScalar solveGroupCacheFriendlyFinish(btCollisionObject** bodies, int numBodies,
                                         const btContactSolverInfo& info) override;

protected:
  btScalar solveGroupCacheFriendlySetup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                        int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                        const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override;
  btScalar solveSingleIteration(int iteration, btCollisionObject** bodies, int numBodies,
                                btPersistentManifold** manifolds, int numManifolds, btTypedConstraint** constraints,
                                int numConstraints, const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override;

private:
  // More rows than this (a humanoid with every joint free) are left to the iterations: each
  // active-set round is an O(n^3) factorisation.
  static constexpr int kMaxBlockRows = 16;
  // block_solve_rows' matrices: fixed capacity, never on the heap.
  using BlockMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxBlockRows, kMaxBlockRows>;
  using BlockVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxBlockRows, 1>;
  // One side (A or B) of one row: the offsets (into the side's Jacobian / velocity block) where
  // its Jacobian is non-zero, entries_[begin, end), and whether its unit-impulse response is.
  struct Side {
    btMultiBody* body = nullptr;
    int jacobian = 0, velocity = 0;  // m_jacAindex / m_deltaVelAindex (or B's)
    int size = 0;                    // 6 + the body's dofs
    int begin = 0, end = 0;
    bool responds = false;
  };
  struct Row {
    Side a, b;
  };
  void list_rows();
  void warm_start_rows();
  void block_solve_rows();
  bool solve_block(int n);
  bool factor(BlockMatrix& sub);
  // Adds `impulse` times a side's unit-impulse response to the solver's and the multibody's
  // velocity changes, as a row's iteration does.
  void apply_impulse(const Side& side, btScalar impulse);
  Side list_side(btMultiBody* body, int jacobian, int velocity);
  btScalar solve_row(btMultiBodySolverConstraint& c, const Row& row);

  bool sparse_ = true;
  bool block_solve_ = false;
  long long iterations_ = 0;
  btScalar warm_start_ = 0;
  // The joint rows' impulses at the end of the last solve, sorted by what the row is: its
  // multibody's user index (the body id), link, constraint type and row. Not by the constraint's
  // address: a robot that rebuilds its multibody (welds freed) gets new constraints, which the
  // allocator may or may not place where old ones were, so an address would hand a new row some
  // old row's impulse in one run and not in another.
  struct Impulse {
    std::array<int, 4> key;  // body, link, type, row
    btScalar impulse;
    bool operator<(const Impulse& o) const { return key < o.key; }
  };
  static std::array<int, 4> row_key(const btMultiBodySolverConstraint& c);
  std::vector<Impulse> last_;
  // block_solve_rows' system and scratch, kept between steps.
  struct Block {
    BlockMatrix matrix, sub, factor;  // factor: the free block's Cholesky factor (lower triangle)
    BlockVector rhs, x, sub_rhs;
    std::vector<int> state, free;  // per row: -1 at its lower bound, +1 at its upper, 0 free
  };
  Block block_;
  std::vector<Row> rows_;     // per m_multiBodyNonContactConstraints entry
  std::vector<int> entries_;  // offsets, see Side
};

}  // namespace rdsim
