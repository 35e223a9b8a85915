#pragma once
#include <Eigen/Core>

#include "rdsim/core/rng.hpp"

// Action distributions over batches (one column per sample). Per-sample results are VectorXf of
// length batch. Gradient functions return d(sum_j w_j f_j)/d(input), with weights w (length
// batch): pass e.g. -advantage/batch for a policy-gradient loss, or a constant for an entropy bonus.
namespace rdsim::nn {

// Softmax policy from logits (actions x batch); log-softmax via log-sum-exp, so huge logits are fine.
class Categorical {
public:
  explicit Categorical(const Eigen::MatrixXf& logits);

  int num_actions() const { return static_cast<int>(log_probs_.rows()); }
  int batch() const { return static_cast<int>(log_probs_.cols()); }
  const Eigen::MatrixXf& log_probs() const { return log_probs_; }  // actions x batch
  const Eigen::MatrixXf& probs() const { return probs_; }          // actions x batch

  // log p(actions[j] | column j). Throws rdsim::Error on an action out of range / wrong length.
  Eigen::VectorXf log_prob(const Eigen::VectorXi& actions) const;
  Eigen::VectorXf entropy() const;
  // One draw per column (inverse CDF with rng.uniform()).
  Eigen::VectorXi sample(Rng& rng) const;
  // Most likely action per column (lowest index on ties).
  Eigen::VectorXi mode() const;

  // d/dlogits of sum_j w_j log p(a_j): w_j (onehot(a_j) - p_j).
  Eigen::MatrixXf log_prob_grad(const Eigen::VectorXi& actions, const Eigen::VectorXf& weights) const;
  // d/dlogits of sum_j w_j H_j: -w_j p_j (log p_j + H_j).
  Eigen::MatrixXf entropy_grad(const Eigen::VectorXf& weights) const;

private:
  Eigen::MatrixXf log_probs_;
  Eigen::MatrixXf probs_;
};

// Diagonal Gaussian with per-sample mean (dims x batch) and a state-independent log-std (dims),
// e.g. the value of an nn::Tensor(dims, 1) (a dims x 1 MatrixXf converts to VectorXf).
class DiagGaussian {
public:
  DiagGaussian(const Eigen::MatrixXf& mean, const Eigen::VectorXf& log_std);

  int dims() const { return static_cast<int>(mean_.rows()); }
  int batch() const { return static_cast<int>(mean_.cols()); }
  const Eigen::MatrixXf& mean() const { return mean_; }
  const Eigen::VectorXf& log_std() const { return log_std_; }

  // Sum over dims of log N(x | mean, std). x is dims x batch.
  Eigen::VectorXf log_prob(const Eigen::MatrixXf& x) const;
  // Same value for every column: sum_d (0.5 + 0.5 log(2 pi) + log_std_d).
  Eigen::VectorXf entropy() const;
  // mean + std * N(0, 1), drawn column by column from rng.normal().
  Eigen::MatrixXf sample(Rng& rng) const;
  const Eigen::MatrixXf& mode() const { return mean_; }

  struct Grad {
    Eigen::MatrixXf mean;     // dims x batch
    Eigen::VectorXf log_std;  // dims (summed over the batch)
  };
  // d/d(mean, log_std) of sum_j w_j log p(x_j): w (x - mu)/sigma^2 and w (((x - mu)/sigma)^2 - 1).
  Grad log_prob_grad(const Eigen::MatrixXf& x, const Eigen::VectorXf& weights) const;
  // d/dlog_std of sum_j w_j H_j (the mean does not affect the entropy): sum_j w_j per dim.
  Eigen::VectorXf entropy_grad_log_std(const Eigen::VectorXf& weights) const;

private:
  Eigen::MatrixXf mean_;
  Eigen::VectorXf log_std_;
};

}  // namespace rdsim::nn
