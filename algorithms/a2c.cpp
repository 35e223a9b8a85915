// Synchronous advantage actor-critic (Mnih et al. 2016, the "A2C" of the common baselines):
// one gradient step per rollout of n_steps x num_envs samples, n-step returns (GAE with
// lambda = 1 by default), RMSprop.
#include "rdsim/algorithms/a2c.hpp"

#include <cmath>

#include "rdsim/algorithms/advantage.hpp"
#include "rdsim/algorithms/on_policy.hpp"
#include "rdsim/core/error.hpp"
#include "memory_footprint.hpp"

namespace rdsim {
namespace {

class A2c final : public OnPolicy {
public:
  A2c(const A2cConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec);
  std::string name() const override { return "a2c"; }

protected:
  Metrics train(double remaining) override {
    const float lr = static_cast<float>(cfg_.anneal_lr ? cfg_.learning_rate * remaining : cfg_.learning_rate);
    optimizer_->set_learning_rate(lr);
    const int B = rollout_.size();
    Eigen::VectorXf adv = rollout_.advantages;
    if (cfg_.normalize_advantage) normalize_advantages(adv);
    const PolicyEval& ev = policy_->evaluate(rollout_.observations, rollout_.actions);
    const float inv_b = 1.0f / static_cast<float>(B);
    // loss = -mean(adv * log p) + vf_coef * mean((R - V)^2) - ent_coef * mean(H)
    const Eigen::VectorXf d_log_prob = -adv * inv_b;
    const Eigen::VectorXf diff = ev.values - rollout_.returns;
    const Eigen::VectorXf d_value = diff * (2.0f * static_cast<float>(cfg_.vf_coef) * inv_b);
    const Eigen::VectorXf d_entropy = Eigen::VectorXf::Constant(B, -static_cast<float>(cfg_.ent_coef) * inv_b);

    const double policy_loss = -(adv.array() * ev.log_probs.array()).cast<double>().mean();
    const double entropy = ev.entropy.cast<double>().mean();
    policy_->zero_grad();
    policy_->backward(d_log_prob, d_entropy, d_value);
    const double demo_loss = add_demonstration_gradient(B);  // 0 without demonstrations.bc_weight
    const nn::ParamList params = policy_->params();
    average_gradients(params);
    const float norm = nn::clip_grad_norm(params, static_cast<float>(cfg_.max_grad_norm));
    optimizer_->step();

    // (The cloning term's evaluate() replaces ev's numbers: the RL ones were read before it.)
    Metrics metrics = {{"policy_loss", policy_loss},
            {"value_loss", diff.cast<double>().squaredNorm() / B},
            {"entropy", entropy},
            {"explained_variance", explained_variance(rollout_.values, rollout_.returns)},
            {"grad_norm", norm},
            {"learning_rate", lr}};
    if (demonstration_term()) {
      metrics.push_back({"demo_bc_loss", demo_loss});
      metrics.push_back({"demo_bc_weight", demonstration_weight()});
    }
    return metrics;
  }

private:
  A2cConfig cfg_;
};

A2c::A2c(const A2cConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec)
    : OnPolicy(network, seed, spec, {config.n_steps, config.gamma, config.gae_lambda}), cfg_(config) {
  // RMSprop as in the baselines' A2C; Adam (with rms_eps) on request.
  if (cfg_.optimizer == "adam")
    use_optimizer(nn::AdamConfig{.lr = static_cast<float>(cfg_.learning_rate), .eps = static_cast<float>(cfg_.rms_eps)});
  else
    use_optimizer(nn::RmsPropConfig{.lr = static_cast<float>(cfg_.learning_rate),
                                    .alpha = static_cast<float>(cfg_.rms_alpha),
                                    .eps = static_cast<float>(cfg_.rms_eps),
                                    .tf_style = cfg_.rms_tf_style});
}

}  // namespace

std::unique_ptr<Algorithm> make_a2c(const A2cConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& /*where*/) {
  return std::make_unique<A2c>(config, network, seed, spec);
}

// The rollout, and one training pass over all of it.
void estimate_memory(const A2cConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  memory::on_policy(c.network, spec, num_envs, p.n_steps, static_cast<double>(p.n_steps) * num_envs, "a2c", c.source, e);
}

}  // namespace rdsim
