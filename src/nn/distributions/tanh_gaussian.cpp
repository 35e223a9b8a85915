#include <cmath>
#include <numbers>
#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/distributions.hpp"

namespace rdsim::nn {

namespace {
const float kHalfLog2Pi = static_cast<float>(0.5 * std::log(2.0 * std::numbers::pi));
const float kLog2 = static_cast<float>(std::numbers::ln2);

// log(1 + exp(x)) without overflow.
float softplus(float x) { return x > 0.0f ? x + std::log1p(std::exp(-x)) : std::log1p(std::exp(x)); }
}  // namespace

TanhGaussian::TanhGaussian(const Eigen::MatrixXf& mean, const Eigen::MatrixXf& log_std, const Eigen::MatrixXf& noise) {
  if (log_std.rows() != mean.rows() || log_std.cols() != mean.cols() || noise.rows() != mean.rows() ||
      noise.cols() != mean.cols())
    throw Error("nn::TanhGaussian: mean, log_std and noise need the same shape (dims x batch)");
  std_noise_ = (log_std.array().exp() * noise.array()).matrix();
  const Eigen::MatrixXf u = mean + std_noise_;
  actions_ = u.array().tanh().matrix();
  log_probs_.resize(mean.cols());
  for (Eigen::Index j = 0; j < mean.cols(); ++j) {
    float lp = 0.0f;
    for (Eigen::Index d = 0; d < mean.rows(); ++d) {
      const float e = noise(d, j), x = u(d, j);
      // log N(u | mean, std) with u - mean = std * noise, minus log(1 - tanh(u)^2).
      lp += -0.5f * e * e - log_std(d, j) - kHalfLog2Pi - 2.0f * (kLog2 - x - softplus(-2.0f * x));
    }
    log_probs_[j] = lp;
  }
}

TanhGaussian::Grad TanhGaussian::backward(const Eigen::MatrixXf& d_actions, const Eigen::VectorXf& d_log_probs) const {
  if (d_actions.rows() != actions_.rows() || d_actions.cols() != actions_.cols() ||
      d_log_probs.size() != actions_.cols())
    throw Error("nn::TanhGaussian::backward: gradient shapes differ from the batch's");
  // d action/du = 1 - a^2; d log pi/du = 2a (the squash term's derivative; the Gaussian term does
  // not depend on u once the noise is fixed); du/dmean = 1, du/dlog_std = std * noise, and
  // log pi has an extra -1 per dim from -log_std.
  const Eigen::ArrayXXf a = actions_.array();
  const Eigen::ArrayXXf du = d_actions.array() * (1.0f - a.square()) + 2.0f * (a.rowwise() * d_log_probs.transpose().array());
  Grad g;
  g.mean = du.matrix();
  g.log_std = (du * std_noise_.array()).matrix();
  g.log_std.rowwise() -= d_log_probs.transpose();
  return g;
}

}  // namespace rdsim::nn
