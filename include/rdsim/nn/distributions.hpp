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

  // KL(this || other) per column: sum_a p_a (log p_a - log q_a). Same shapes required.
  Eigen::VectorXf kl_divergence(const Categorical& other) const;
  // The Fisher information of each column w.r.t. its logits times `tangent` (actions x batch):
  // (diag(p) - p p^T) t, column by column (the Hessian of KL(p || q) at q = p).
  Eigen::MatrixXf fisher_product(const Eigen::MatrixXf& tangent) const;

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

  // KL(this || other) per column: sum_d log(s_q/s_p) + (s_p^2 + (m_p - m_q)^2) / (2 s_q^2) - 1/2.
  Eigen::VectorXf kl_divergence(const DiagGaussian& other) const;
  // The Fisher information w.r.t. (mean, log_std) times a tangent: mean part t_mean / sigma^2 per
  // sample; the log-std part is 2 t_log_std for every sample (the caller sums over its batch).
  Eigen::MatrixXf fisher_product_mean(const Eigen::MatrixXf& tangent_mean) const;

private:
  Eigen::MatrixXf mean_;
  Eigen::VectorXf log_std_;
};

// The tanh-squashed Gaussian of soft actor-critic (Haarnoja et al. 2018), reparameterised:
// u = mean + exp(log_std) * noise, action = tanh(u) in (-1, 1), with one log-std per sample and
// dimension (a network output; the caller clamps it). log pi(action) = log N(u | mean, std)
// - sum_d log(1 - tanh(u_d)^2), the last term computed stably as 2 (log 2 - u - softplus(-2u)).
class TanhGaussian {
public:
  // mean, log_std, noise: dims x batch; noise holds standard-normal draws.
  TanhGaussian(const Eigen::MatrixXf& mean, const Eigen::MatrixXf& log_std, const Eigen::MatrixXf& noise);

  const Eigen::MatrixXf& actions() const { return actions_; }   // dims x batch
  const Eigen::VectorXf& log_probs() const { return log_probs_; }  // batch

  // The deterministic action tanh(mean).
  static Eigen::MatrixXf mode(const Eigen::MatrixXf& mean) { return mean.array().tanh().matrix(); }

  struct Grad {
    Eigen::MatrixXf mean;     // dims x batch
    Eigen::MatrixXf log_std;  // dims x batch
  };
  // d/d(mean, log_std) of sum_j [sum_d g_a(d, j) action(d, j) + g_l(j) log_prob(j)], the noise
  // held fixed: what the actor loss of SAC needs (g_a from dQ/daction, g_l = alpha / batch).
  Grad backward(const Eigen::MatrixXf& d_actions, const Eigen::VectorXf& d_log_probs) const;

private:
  Eigen::MatrixXf std_noise_;  // exp(log_std) * noise = du/dlog_std
  Eigen::MatrixXf actions_;
  Eigen::VectorXf log_probs_;
};

}  // namespace rdsim::nn
