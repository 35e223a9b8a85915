#include <cmath>
#include <numbers>
#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/distributions.hpp"

namespace rdsim::nn {

namespace {
const float kHalfLog2Pi = static_cast<float>(0.5 * std::log(2.0 * std::numbers::pi));

void check_batch(const Eigen::MatrixXf& x, int dims, int batch, const char* who) {
  if (x.rows() != dims || x.cols() != batch)
    throw Error(std::string(who) + ": got " + std::to_string(x.rows()) + "x" +
                std::to_string(x.cols()) + " values, expected " + std::to_string(dims) + "x" +
                std::to_string(batch));
}
}  // namespace

DiagGaussian::DiagGaussian(const Eigen::MatrixXf& mean, const Eigen::VectorXf& log_std)
    : mean_(mean), log_std_(log_std) {
  if (log_std.size() != mean.rows())
    throw Error("nn::DiagGaussian: log_std has " + std::to_string(log_std.size()) +
                " entries for a mean of " + std::to_string(mean.rows()) + " dims");
}

Eigen::VectorXf DiagGaussian::log_prob(const Eigen::MatrixXf& x) const {
  check_batch(x, dims(), batch(), "nn::DiagGaussian::log_prob");
  const Eigen::ArrayXf inv_std = (-log_std_.array()).exp();
  const Eigen::ArrayXXf z = (x - mean_).array().colwise() * inv_std;
  const float norm = log_std_.sum() + static_cast<float>(dims()) * kHalfLog2Pi;
  return (-0.5f * z.square().colwise().sum() - norm).transpose().matrix();
}

Eigen::VectorXf DiagGaussian::entropy() const {
  const float h = log_std_.sum() + static_cast<float>(dims()) * (0.5f + kHalfLog2Pi);
  return Eigen::VectorXf::Constant(batch(), h);
}

Eigen::MatrixXf DiagGaussian::sample(Rng& rng) const {
  const Eigen::VectorXf std = log_std_.array().exp().matrix();
  Eigen::MatrixXf out(dims(), batch());
  for (int j = 0; j < batch(); ++j)
    for (int d = 0; d < dims(); ++d)
      out(d, j) = mean_(d, j) + std[d] * static_cast<float>(rng.normal());
  return out;
}

DiagGaussian::Grad DiagGaussian::log_prob_grad(const Eigen::MatrixXf& x,
                                               const Eigen::VectorXf& weights) const {
  check_batch(x, dims(), batch(), "nn::DiagGaussian::log_prob_grad");
  if (weights.size() != batch())
    throw Error("nn::DiagGaussian::log_prob_grad: got " + std::to_string(weights.size()) +
                " weights for a batch of " + std::to_string(batch()));
  const Eigen::ArrayXf inv_std = (-log_std_.array()).exp();
  const Eigen::ArrayXXf z = (x - mean_).array().colwise() * inv_std;
  Grad g;
  g.mean = ((z.colwise() * inv_std).matrix()) * weights.asDiagonal();
  g.log_std = ((z.square() - 1.0f).matrix()) * weights;
  return g;
}

Eigen::VectorXf DiagGaussian::entropy_grad_log_std(const Eigen::VectorXf& weights) const {
  if (weights.size() != batch())
    throw Error("nn::DiagGaussian::entropy_grad_log_std: got " + std::to_string(weights.size()) +
                " weights for a batch of " + std::to_string(batch()));
  return Eigen::VectorXf::Constant(dims(), weights.sum());
}

Eigen::VectorXf DiagGaussian::kl_divergence(const DiagGaussian& other) const {
  if (other.dims() != dims() || other.batch() != batch())
    throw Error("nn::DiagGaussian::kl_divergence: the two distributions differ in shape");
  const Eigen::ArrayXf var_p = (2.0f * log_std_.array()).exp();
  const Eigen::ArrayXf inv_var_q = (-2.0f * other.log_std_.array()).exp();
  const Eigen::ArrayXXf diff2 = (mean_ - other.mean_).array().square();
  const float constant = (other.log_std_ - log_std_).sum() + 0.5f * (var_p * inv_var_q).sum() -
                         0.5f * static_cast<float>(dims());
  return ((0.5f * (diff2.colwise() * inv_var_q)).colwise().sum() + constant).transpose().matrix();
}

Eigen::MatrixXf DiagGaussian::fisher_product_mean(const Eigen::MatrixXf& tangent_mean) const {
  check_batch(tangent_mean, dims(), batch(), "nn::DiagGaussian::fisher_product_mean");
  const Eigen::ArrayXf inv_var = (-2.0f * log_std_.array()).exp();
  return (tangent_mean.array().colwise() * inv_var).matrix();
}

}  // namespace rdsim::nn
