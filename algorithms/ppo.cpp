// Proximal Policy Optimisation with the clipped surrogate objective (Schulman et al. 2017),
// as in the common baselines: GAE, several epochs of shuffled minibatches, per-minibatch
// advantage normalisation, optional value clipping, entropy bonus, global grad-norm clipping,
// linear learning-rate / clip-range annealing, approx-KL early stopping.
#include "rdsim/algorithms/ppo.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "rdsim/algorithms/advantage.hpp"
#include "rdsim/algorithms/on_policy.hpp"
#include "rdsim/core/error.hpp"
#include "memory_footprint.hpp"

namespace rdsim {
namespace {

class Ppo final : public OnPolicy {
public:
  Ppo(const PpoConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec)
      : OnPolicy(network, seed, spec, {config.n_steps, config.gamma, config.gae_lambda}), cfg_(config) {
    use_optimizer(nn::AdamConfig{.lr = static_cast<float>(cfg_.learning_rate), .eps = static_cast<float>(cfg_.adam_eps)});
  }

  std::string name() const override { return "ppo"; }

protected:
  Metrics train(double remaining) override;

private:
  struct Minibatch {
    Eigen::MatrixXf obs, actions;
    Eigen::VectorXf old_log_probs, old_values, advantages, returns;
  };
  void gather(const std::vector<int>& indices, int begin, int count);

  PpoConfig cfg_;
  Minibatch mb_;
  std::vector<int> order_;
};

void Ppo::gather(const std::vector<int>& idx, int begin, int count) {
  const auto& r = rollout_;
  mb_.obs.resize(r.observations.rows(), count);
  mb_.actions.resize(r.actions.rows(), count);
  mb_.old_log_probs.resize(count);
  mb_.old_values.resize(count);
  mb_.advantages.resize(count);
  mb_.returns.resize(count);
  for (int j = 0; j < count; ++j) {
    const int i = idx[static_cast<std::size_t>(begin + j)];
    mb_.obs.col(j) = r.observations.col(i);
    mb_.actions.col(j) = r.actions.col(i);
    mb_.old_log_probs[j] = r.log_probs[i];
    mb_.old_values[j] = r.values[i];
    mb_.advantages[j] = r.advantages[i];
    mb_.returns[j] = r.returns[i];
  }
}

Metrics Ppo::train(double remaining) {
  const float lr = static_cast<float>(cfg_.anneal_lr ? cfg_.learning_rate * remaining : cfg_.learning_rate);
  const float clip = static_cast<float>(cfg_.anneal_clip_range ? cfg_.clip_range * remaining : cfg_.clip_range);
  const float clip_vf = static_cast<float>(cfg_.clip_range_vf);
  optimizer_->set_learning_rate(lr);
  const nn::ParamList params = policy_->params();

  const int n = rollout_.size();
  order_.resize(static_cast<std::size_t>(n));
  double sum_pg = 0, sum_v = 0, sum_ent = 0, sum_kl = 0, sum_clipped = 0, sum_norm = 0, sum_demo = 0;
  long long minibatches = 0, samples = 0;
  bool stop = false;
  for (int epoch = 0; epoch < cfg_.n_epochs && !stop; ++epoch) {
    std::iota(order_.begin(), order_.end(), 0);
    for (int i = n - 1; i > 0; --i) {  // Fisher-Yates from our own Rng: identical on every platform
      std::swap(order_[static_cast<std::size_t>(i)], order_[shuffle_rng_.below(static_cast<std::uint64_t>(i) + 1)]);
    }
    for (int begin = 0; begin < n && !stop; begin += cfg_.batch_size) {
      const int B = std::min(cfg_.batch_size, n - begin);
      gather(order_, begin, B);
      Eigen::VectorXf adv = mb_.advantages;
      if (cfg_.normalize_advantage) normalize_advantages(adv);
      const PolicyEval& ev = policy_->evaluate(mb_.obs, mb_.actions);
      const Eigen::ArrayXf log_ratio = (ev.log_probs - mb_.old_log_probs).array();
      const Eigen::ArrayXf ratio = log_ratio.exp();
      double approx_kl = ((ratio - 1.0f) - log_ratio).cast<double>().mean();
      if (cfg_.target_kl > 0 && communicator().size() > 1) {
        // Every rank must take the same decision: the mean over the ranks decides.
        communicator().allreduce_sum(&approx_kl, 1);
        approx_kl /= communicator().size();
      }
      if (cfg_.target_kl > 0 && approx_kl > 1.5 * cfg_.target_kl) {
        stop = true;  // the baselines' early stop: this minibatch is not applied
        break;
      }

      Eigen::VectorXf d_log_prob(B), d_value(B);
      double pg_loss = 0, v_loss = 0, clipped = 0;
      const float inv_b = 1.0f / static_cast<float>(B);
      for (int j = 0; j < B; ++j) {
        const float a = adv[j], rt = ratio[j];
        const float rc = std::clamp(rt, 1.0f - clip, 1.0f + clip);
        const float s1 = a * rt, s2 = a * rc;
        pg_loss -= std::min(s1, s2);
        // -min(s1, s2): the unclipped branch carries the gradient a * ratio (d ratio/d log p = ratio).
        d_log_prob[j] = s1 <= s2 ? -a * rt * inv_b : 0.0f;
        clipped += std::abs(rt - 1.0f) > clip ? 1.0 : 0.0;

        const float v = ev.values[j], ret = mb_.returns[j];
        float dv = 2.0f * (v - ret);
        float loss = (v - ret) * (v - ret);
        if (clip_vf > 0.0f) {
          const float old = mb_.old_values[j];
          const float vc = old + std::clamp(v - old, -clip_vf, clip_vf);
          const float loss_c = (vc - ret) * (vc - ret);
          if (loss_c > loss) {  // the clipped branch is pessimistic; it is constant in v when clipped
            loss = loss_c;
            dv = vc == v ? 2.0f * (vc - ret) : 0.0f;
          }
        }
        v_loss += loss;
        d_value[j] = static_cast<float>(cfg_.vf_coef) * dv * inv_b;
      }
      const Eigen::VectorXf d_entropy = Eigen::VectorXf::Constant(B, -static_cast<float>(cfg_.ent_coef) * inv_b);

      sum_ent += ev.entropy.cast<double>().mean();  // before the cloning term's evaluate() replaces ev
      policy_->zero_grad();
      policy_->backward(d_log_prob, d_entropy, d_value);
      sum_demo += add_demonstration_gradient(B);  // 0 without demonstrations.bc_weight
      average_gradients(params);
      sum_norm += nn::clip_grad_norm(params, static_cast<float>(cfg_.max_grad_norm));
      optimizer_->step();

      sum_pg += pg_loss / B;
      sum_v += v_loss / B;
      sum_kl += approx_kl;
      sum_clipped += clipped;
      samples += B;
      ++minibatches;
    }
  }
  const double m = std::max<long long>(minibatches, 1);
  Metrics metrics = {{"policy_loss", sum_pg / m},
          {"value_loss", sum_v / m},
          {"entropy", sum_ent / m},
          {"approx_kl", sum_kl / m},
          {"clip_fraction", samples ? sum_clipped / static_cast<double>(samples) : 0.0},
          {"explained_variance", explained_variance(rollout_.values, rollout_.returns)},
          {"grad_norm", sum_norm / m},
          {"learning_rate", lr},
          {"clip_range", clip},
          {"minibatches", static_cast<double>(minibatches)}};
  if (demonstration_term()) {
    metrics.push_back({"demo_bc_loss", sum_demo / m});
    metrics.push_back({"demo_bc_weight", demonstration_weight()});
  }
  return metrics;
}

}  // namespace

std::unique_ptr<Algorithm> make_ppo(const PpoConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& /*where*/) {
  return std::make_unique<Ppo>(config, network, seed, spec);
}

// The rollout, and training passes over batch_size samples (at most the rollout).
void estimate_memory(const PpoConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  const double rollout = static_cast<double>(p.n_steps) * num_envs;
  memory::on_policy(c.network, spec, num_envs, p.n_steps, std::min<double>(p.batch_size, rollout), "ppo", c.source, e);
}

}  // namespace rdsim
