#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/nn/distributions.hpp"

namespace rdsim::nn {

Categorical::Categorical(const Eigen::MatrixXf& logits) {
  if (logits.rows() == 0) throw Error("nn::Categorical: logits need at least one action row");
  // Subtracting the column maximum keeps exp() in range for any logits.
  const Eigen::RowVectorXf max = logits.colwise().maxCoeff();
  log_probs_ = logits.rowwise() - max;
  const Eigen::RowVectorXf log_sum = log_probs_.array().exp().colwise().sum().log().matrix();
  log_probs_.rowwise() -= log_sum;
  probs_ = log_probs_.array().exp().matrix();
}

namespace {

void check_actions(const Eigen::VectorXi& actions, int num_actions, int batch) {
  if (actions.size() != batch)
    throw Error("nn::Categorical: got " + std::to_string(actions.size()) + " actions for a batch of " +
                std::to_string(batch));
  for (Eigen::Index j = 0; j < actions.size(); ++j)
    if (actions[j] < 0 || actions[j] >= num_actions)
      throw Error("nn::Categorical: action " + std::to_string(actions[j]) + " outside [0, " +
                  std::to_string(num_actions) + ")");
}

void check_weights(const Eigen::VectorXf& weights, int batch, const char* who) {
  if (weights.size() != batch)
    throw Error(std::string(who) + ": got " + std::to_string(weights.size()) +
                " weights for a batch of " + std::to_string(batch));
}

}  // namespace

Eigen::VectorXf Categorical::log_prob(const Eigen::VectorXi& actions) const {
  check_actions(actions, num_actions(), batch());
  Eigen::VectorXf out(batch());
  for (int j = 0; j < batch(); ++j) out[j] = log_probs_(actions[j], j);
  return out;
}

Eigen::VectorXf Categorical::entropy() const {
  return -(probs_.cwiseProduct(log_probs_)).colwise().sum().transpose();
}

Eigen::VectorXi Categorical::sample(Rng& rng) const {
  Eigen::VectorXi out(batch());
  const int last = num_actions() - 1;
  for (int j = 0; j < batch(); ++j) {
    const float u = static_cast<float>(rng.uniform());
    float cumulative = 0.0f;
    int a = 0;
    // Rounding can leave the total just below 1: the last action takes what remains.
    for (; a < last; ++a) {
      cumulative += probs_(a, j);
      if (u < cumulative) break;
    }
    out[j] = a;
  }
  return out;
}

Eigen::VectorXi Categorical::mode() const {
  Eigen::VectorXi out(batch());
  for (int j = 0; j < batch(); ++j) log_probs_.col(j).maxCoeff(&out[j]);
  return out;
}

Eigen::MatrixXf Categorical::log_prob_grad(const Eigen::VectorXi& actions,
                                           const Eigen::VectorXf& weights) const {
  check_actions(actions, num_actions(), batch());
  check_weights(weights, batch(), "nn::Categorical::log_prob_grad");
  Eigen::MatrixXf grad = -probs_;
  for (int j = 0; j < batch(); ++j) grad(actions[j], j) += 1.0f;
  return grad * weights.asDiagonal();
}

Eigen::MatrixXf Categorical::entropy_grad(const Eigen::VectorXf& weights) const {
  check_weights(weights, batch(), "nn::Categorical::entropy_grad");
  const Eigen::RowVectorXf h = entropy().transpose();
  const Eigen::MatrixXf inner = log_probs_.rowwise() + h;
  return -(probs_.cwiseProduct(inner)) * weights.asDiagonal();
}

Eigen::VectorXf Categorical::kl_divergence(const Categorical& other) const {
  if (other.num_actions() != num_actions() || other.batch() != batch())
    throw Error("nn::Categorical::kl_divergence: the two distributions differ in shape");
  return probs_.cwiseProduct(log_probs_ - other.log_probs_).colwise().sum().transpose();
}

Eigen::MatrixXf Categorical::fisher_product(const Eigen::MatrixXf& tangent) const {
  if (tangent.rows() != num_actions() || tangent.cols() != batch())
    throw Error("nn::Categorical::fisher_product: tangent shape differs from the logits'");
  const Eigen::RowVectorXf pt = probs_.cwiseProduct(tangent).colwise().sum();
  return probs_.cwiseProduct(tangent) - probs_ * pt.asDiagonal();
}

}  // namespace rdsim::nn
