#pragma once
// Cholesky factorisation and solve for the small symmetric positive definite systems of the sim
// layer's inner loops (a robot's mass matrix, a block of joint rows: at most a few tens of rows,
// several per physics step), written out where Eigen's general routines cost more than the
// arithmetic. Only src/sim includes this.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace rdsim {

// Cholesky factor L of the leading m x m block of `a` (symmetric positive definite), in place:
// L's strictly lower triangle, and 1 / L(j, j) on the diagonal (the solves multiply by it: a
// division's latency, a dozen cycles, chained through every row, was most of their time). False
// when a pivot is not clearly positive (a singular matrix).
inline bool cholesky(Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> a, int m) {
  double largest = 0;
  for (int i = 0; i < m; ++i) largest = std::max(largest, std::abs(a(i, i)));
  for (int j = 0; j < m; ++j) {
    double d = a(j, j);
    for (int k = 0; k < j; ++k) d -= a(j, k) * a(j, k);
    if (!(d > 1e-12 * largest)) return false;
    const double inverse = 1.0 / std::sqrt(d);
    a(j, j) = inverse;
    for (int i = j + 1; i < m; ++i) {
      double v = a(i, j);
      for (int k = 0; k < j; ++k) v -= a(i, k) * a(j, k);
      a(i, j) = v * inverse;
    }
  }
  return true;
}

// Solves L L^T x = b in place for the factor cholesky() left.
template <typename Vector>
inline void cholesky_solve(const Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>& l, int m, Vector& b) {
  for (int i = 0; i < m; ++i) {
    double v = b(i);
    for (int k = 0; k < i; ++k) v -= l(i, k) * b(k);
    b(i) = v * l(i, i);
  }
  for (int i = m - 1; i >= 0; --i) {
    double v = b(i);
    for (int k = i + 1; k < m; ++k) v -= l(k, i) * b(k);
    b(i) = v * l(i, i);
  }
}

}  // namespace rdsim
