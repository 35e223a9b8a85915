#pragma once
// Finite-difference gradient checks of the float networks against a double-precision reference
// that holds the same parameters (`ref.tensors`, in params() order) and computes the same loss
// (`ref.loss(x, c)`, e.g. sum(C .* net(x))).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "rdsim/nn/param.hpp"

namespace gradcheck {

inline double rel_error(double a, double b) { return std::abs(a - b) / std::max(1e-3, std::abs(a) + std::abs(b)); }

// Compares the analytic gradients (grad_x for the input, params' grads) with central differences
// of the reference's loss.
template <class Reference>
void check(Reference& ref, const Eigen::MatrixXd& xd, const Eigen::MatrixXd& cd, const Eigen::MatrixXf& grad_x,
           const rdsim::nn::ParamList& params) {
  const double h = 1e-6;
  for (Eigen::Index j = 0; j < xd.cols(); ++j)
    for (Eigen::Index i = 0; i < xd.rows(); ++i) {
      Eigen::MatrixXd xp = xd, xm = xd;
      xp(i, j) += h;
      xm(i, j) -= h;
      const double numeric = (ref.loss(xp, cd) - ref.loss(xm, cd)) / (2 * h);
      INFO("input(" << i << "," << j << ")");
      CHECK(rel_error(grad_x(i, j), numeric) < 1e-4);
    }
  for (size_t t = 0; t < params.size(); ++t)
    for (Eigen::Index k = 0; k < params[t].value->size(); ++k) {
      double& w = ref.tensors[t].data()[k];
      const double saved = w;
      w = saved + h;
      const double lp = ref.loss(xd, cd);
      w = saved - h;
      const double lm = ref.loss(xd, cd);
      w = saved;
      INFO(params[t].name << "[" << k << "]");
      CHECK(rel_error(params[t].grad->data()[k], (lp - lm) / (2 * h)) < 1e-4);
    }
}

}  // namespace gradcheck
