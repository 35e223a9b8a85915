// Trust region policy optimisation (Schulman et al. 2015) as in Stable-Baselines3-contrib:
// on-policy rollouts with GAE (OnPolicy), then one natural-gradient policy step per rollout --
// the surrogate's gradient g, the direction x = F^-1 g by conjugate gradient on Fisher-vector
// products, the largest step along x whose quadratic KL estimate is target_kl, and a
// backtracking line search that accepts the first step with mean KL(old || new) < target_kl and
// a better surrogate -- and n_critic_updates epochs of Adam minibatches on the value function.
// Under MPI every rank collects its own rollout (of the same size), and g, every Fisher-vector
// product, the surrogate and KL values and the critic's gradients are averaged over the ranks:
// every rank then takes the same step, the one of all ranks' rollouts together.
#include "rdsim/algorithms/trpo.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/advantage.hpp"
#include "rdsim/algorithms/gradient_averaging.hpp"
#include "rdsim/algorithms/on_policy.hpp"
#include "rdsim/core/error.hpp"
#include "memory_footprint.hpp"

namespace rdsim {

namespace trpo {

Eigen::VectorXf conjugate_gradient(const std::function<Eigen::VectorXf(const Eigen::VectorXf&)>& product,
                                   const Eigen::VectorXf& b, int max_steps, float residual_tol) {
  Eigen::VectorXf x = Eigen::VectorXf::Zero(b.size());
  Eigen::VectorXf r = b, p = b;
  float rr = r.squaredNorm();
  for (int i = 0; i < max_steps && rr > residual_tol; ++i) {
    const Eigen::VectorXf ap = product(p);
    const float alpha = rr / p.dot(ap);
    x += alpha * p;
    r -= alpha * ap;
    const float rr_next = r.squaredNorm();
    p = r + (rr_next / rr) * p;
    rr = rr_next;
  }
  return x;
}

}  // namespace trpo

namespace {

const NetworkConfig& checked_network(const NetworkConfig& network, const Spec& spec, const std::string& where) {
  if (network.shared)
    throw Error(where + ": network.shared: \"trpo\" needs separate policy and value networks (expected false)");
  if (spec.observation.type == ObsType::UInt8)
    throw Error(where + ": algorithm: \"trpo\" needs vector observations, env \"" + spec.env_name +
                "\" gives pixels (use env.observation \"ground_truth\")");
  return network;
}

class Trpo final : public OnPolicy {
public:
  Trpo(const TrpoConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
       const std::string& where)
      : OnPolicy(checked_network(network, spec, where), seed, spec, {config.n_steps, config.gamma, config.gae_lambda}),
        cfg_(config) {
    nn::AdamConfig adam;
    adam.lr = static_cast<float>(cfg_.learning_rate);
    optimizer_ = std::make_unique<nn::Adam>(policy_->value_params(), adam);  // the critic's; the policy steps by CG
  }

  std::string name() const override { return "trpo"; }
  bool data_parallel() const override { return true; }

protected:
  Metrics train(double remaining) override;

private:
  // Mean of ratio * advantage over the rollout for the last evaluate(): the surrogate objective.
  double surrogate(const Eigen::VectorXf& log_probs, const Eigen::VectorXf& adv) const {
    return ((log_probs - rollout_.log_probs).array().exp() * adv.array()).cast<double>().mean();
  }
  // The mean of `values` over the ranks (of their rollouts; all of the same size).
  template <std::size_t N>
  std::array<double, N> over_ranks(std::array<double, N> values) const {
    average_values(communicator(), values.data(), N);
    return values;
  }
  double train_critic();

  TrpoConfig cfg_;
  std::vector<int> order_;
};

Metrics Trpo::train(double /*remaining*/) {
  const int n = rollout_.size();
  const float inv_n = 1.0f / static_cast<float>(n);
  Eigen::VectorXf adv = rollout_.advantages;
  if (cfg_.normalize_advantage && n > 1) {
    const float mean = adv.mean();
    const float stddev = std::sqrt((adv.array() - mean).square().sum() / static_cast<float>(n - 1));
    adv = (adv.array() - mean) / (stddev + 1e-8f);
  }
  const nn::ParamList params = policy_->policy_params();

  // The surrogate's gradient at the rollout's policy: d/dlog pi of mean(ratio * adv) = ratio * adv / n.
  const PolicyEval& start = policy_->evaluate(rollout_.observations, rollout_.actions);
  const ActorCritic::Distributions old = policy_->distributions();
  const double objective = over_ranks<1>({surrogate(start.log_probs, adv)})[0];
  const Eigen::VectorXf ratio = (start.log_probs - rollout_.log_probs).array().exp().matrix();
  policy_->zero_grad();
  policy_->backward(ratio.cwiseProduct(adv) * inv_n, Eigen::VectorXf(), Eigen::VectorXf::Zero(n));
  average_gradients(params);
  const Eigen::VectorXf g = nn::flatten_grads(params);

  // Natural gradient direction x = (F + damping I)^-1 g, and the step whose quadratic KL
  // estimate 0.5 s^T F s equals target_kl.
  const auto damping = static_cast<float>(cfg_.cg_damping);
  const auto fisher = [&](const Eigen::VectorXf& v) -> Eigen::VectorXf {
    Eigen::VectorXf fv = policy_->fisher_vector_product(v);
    average_values(communicator(), fv.data(), static_cast<std::size_t>(fv.size()));
    return fv + damping * v;
  };
  const Eigen::VectorXf x = trpo::conjugate_gradient(fisher, g, cfg_.cg_max_steps);
  const float xfx = x.dot(fisher(x));
  const float max_step = xfx > 0.0f ? std::sqrt(2.0f * static_cast<float>(cfg_.target_kl) / xfx) : 0.0f;

  // Backtracking line search.
  const Eigen::VectorXf theta_old = nn::flatten_values(params);
  float coef = 1.0f;
  bool accepted = false;
  double kl = 0.0, improved = objective;
  int tries = 0;
  for (; tries < cfg_.line_search_max_iter && max_step > 0.0f; ++tries) {
    nn::assign_values(params, theta_old + coef * max_step * x);
    const PolicyEval& ev = policy_->evaluate(rollout_.observations, rollout_.actions);
    const std::array<double, 2> kl_and_surrogate = over_ranks<2>({policy_->mean_kl(old), surrogate(ev.log_probs, adv)});
    kl = kl_and_surrogate[0];
    improved = kl_and_surrogate[1];
    if (kl < cfg_.target_kl && improved > objective) {
      accepted = true;
      ++tries;
      break;
    }
    coef *= static_cast<float>(cfg_.line_search_shrinking_factor);
  }
  if (!accepted) {
    nn::assign_values(params, theta_old);
    kl = 0.0;
    improved = objective;
  }

  const double value_loss = train_critic();
  return {{"policy_objective", improved - objective},
          {"kl_divergence", kl},
          {"step_accepted", accepted ? 1.0 : 0.0},
          {"line_search_tries", static_cast<double>(tries)},
          {"step_size", accepted ? static_cast<double>(coef * max_step) : 0.0},
          {"gradient_norm", g.norm()},
          {"value_loss", value_loss},
          {"explained_variance", explained_variance(rollout_.values, rollout_.returns)}};
}

// n_critic_updates epochs of shuffled minibatches regressing V on the GAE returns; the mean
// squared error of the last epoch.
double Trpo::train_critic() {
  const int n = rollout_.size();
  order_.resize(static_cast<std::size_t>(n));
  Eigen::MatrixXf obs, actions;
  Eigen::VectorXf returns;
  double loss_sum = 0.0;
  for (int epoch = 0; epoch < cfg_.n_critic_updates; ++epoch) {
    std::iota(order_.begin(), order_.end(), 0);
    for (int i = n - 1; i > 0; --i)  // Fisher-Yates from our own Rng: identical on every platform
      std::swap(order_[static_cast<std::size_t>(i)], order_[shuffle_rng_.below(static_cast<std::uint64_t>(i) + 1)]);
    loss_sum = 0.0;
    for (int begin = 0; begin < n; begin += cfg_.batch_size) {
      const int b = std::min(cfg_.batch_size, n - begin);
      obs.resize(rollout_.observations.rows(), b);
      actions.resize(rollout_.actions.rows(), b);
      returns.resize(b);
      for (int j = 0; j < b; ++j) {
        const int i = order_[static_cast<std::size_t>(begin + j)];
        obs.col(j) = rollout_.observations.col(i);
        actions.col(j) = rollout_.actions.col(i);
        returns[j] = rollout_.returns[i];
      }
      const PolicyEval& ev = policy_->evaluate(obs, actions);
      const Eigen::VectorXf diff = ev.values - returns;
      policy_->zero_grad();
      policy_->backward(Eigen::VectorXf::Zero(b), Eigen::VectorXf(), diff * (2.0f / static_cast<float>(b)));
      average_gradients(optimizer_->params());
      optimizer_->step();
      loss_sum += diff.cast<double>().squaredNorm();
    }
  }
  return cfg_.n_critic_updates > 0 ? loss_sum / n : 0.0;
}

}  // namespace

std::unique_ptr<Algorithm> make_trpo(const TrpoConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                     const Spec& spec, const std::string& where) {
  return std::make_unique<Trpo>(config, network, seed, spec, where);
}

// The whole rollout in one pass (the natural-gradient step), plus conjugate-gradient vectors.
void estimate_memory(const TrpoConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  memory::on_policy(c.network, spec, num_envs, p.n_steps, static_cast<double>(p.n_steps) * num_envs, "trpo", c.source, e);
}

}  // namespace rdsim
