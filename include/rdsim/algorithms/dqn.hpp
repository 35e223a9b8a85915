#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Deep Q-Learning (algorithms/dqn.cpp): its config, its factory, and the pieces worth testing
// on their own.
namespace rdsim {

// The "dqn" object of a training config. Defaults: Stable-Baselines3's.
struct DqnConfig {
  double learning_rate = 1e-4;
  bool anneal_lr = false;
  int batch_size = 32;
  long long buffer_size = 1000000;
  long long learning_starts = 100;
  double gamma = 0.99;
  long long target_update_interval = 10000;
  double tau = 1.0;
  int train_freq = 4;
  int gradient_steps = 1;
  double exploration_fraction = 0.1;
  double exploration_initial_eps = 1.0;
  double exploration_final_eps = 0.05;
  double max_grad_norm = 10.0;
  bool double_q = false;
  bool huber = true;
  int n_step = 1;
};

template <class V, class C>
  requires config::Describes<C, DqnConfig>
void describe(V& v, C& c) {
  constexpr long long max_steps = 1'000'000'000'000LL;
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1.0}, "Adam step size");
  v.field("anneal_lr", c.anneal_lr, "learning rate decays linearly to 0 over total_timesteps");
  v.field("batch_size", c.batch_size, config::Range{1, 1'000'000}, "transitions per gradient step");
  v.field("buffer_size", c.buffer_size, config::Range{1LL, 100'000'000LL}, "replay buffer capacity (transitions)");
  v.field("learning_starts", c.learning_starts, config::Range{0LL, max_steps}, "env steps before learning starts");
  v.field("gamma", c.gamma, config::Range{0.0, 1.0}, "discount factor");
  v.field("target_update_interval", c.target_update_interval, config::Range{1LL, max_steps},
          "env steps between target-network updates");
  v.field("tau", c.tau, config::Range{0.0, 1.0}, "target update: 1 = hard copy, < 1 = Polyak averaging");
  v.field("train_freq", c.train_freq, config::Range{1, 1'000'000}, "env steps per env between training phases");
  v.field("gradient_steps", c.gradient_steps, config::Range{1, 1'000'000}, "gradient steps per training phase");
  v.field("exploration_fraction", c.exploration_fraction, config::Range{0.0, 1.0},
          "fraction of total_timesteps over which epsilon falls from initial to final");
  v.field("exploration_initial_eps", c.exploration_initial_eps, config::Range{0.0, 1.0}, "epsilon at the start");
  v.field("exploration_final_eps", c.exploration_final_eps, config::Range{0.0, 1.0},
          "epsilon after the decay (and of `rdsim replay --stochastic`)");
  v.field("max_grad_norm", c.max_grad_norm, config::Range{1e-9, 1e9}, "global gradient-norm clip");
  v.field("double_q", c.double_q, "double Q-learning targets (van Hasselt et al.)");
  v.field("huber", c.huber, "Huber (smooth L1) TD loss, else squared error");
  v.field("n_step", c.n_step, config::Range{1, 1000},
          "rewards summed per TD target (n-step returns; 1 = one-step Q-learning)");
  v.check(c.exploration_initial_eps >= c.exploration_final_eps, "exploration_final_eps",
          "expected at most exploration_initial_eps (" + nlohmann::json(c.exploration_initial_eps).dump() +
              "): epsilon falls from the initial to the final value");
  v.check(c.batch_size <= c.buffer_size, "batch_size",
          "expected at most buffer_size (" + std::to_string(c.buffer_size) + ")");
}

// rdsim::Error naming `where` (the config file) when the env has continuous actions, and with `her`
// when the env has no goals or n_step is above 1. (Whether the replay buffer fits in memory is the
// training run's memory estimate: estimate_algorithm_memory.)
std::unique_ptr<Algorithm> make_dqn(const DqnConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where, const std::optional<HerConfig>& her = {});

}  // namespace rdsim

namespace rdsim::dqn {

// TD targets y_j = r_j + gamma^k_j * (1 - terminated_j) * Q_target(s'_j, a*_j), k_j = steps[j]
// (the env steps r_j sums: n-step returns) or 1 without `steps`.
// a*_j = argmax_a next_q_target(:, j), or with double Q-learning (next_q_online != nullptr)
// a*_j = argmax_a next_q_online(:, j), evaluated by the target network (van Hasselt et al.).
// Q matrices are actions x batch. Truncated transitions carry terminated = 0: they bootstrap.
Eigen::VectorXf td_targets(const Eigen::VectorXf& rewards, const Eigen::VectorXf& terminated,
                           const Eigen::MatrixXf& next_q_target, const Eigen::MatrixXf* next_q_online,
                           float gamma, const Eigen::VectorXf* steps = nullptr);

// Mean over the batch of a TD loss of (prediction - target) and its gradient w.r.t. each
// prediction (already divided by the batch size).
struct TdLoss {
  float loss = 0.0f;
  Eigen::VectorXf grad;
};
// Huber / smooth-L1 with threshold 1: 0.5 d^2 for |d| <= 1, |d| - 0.5 beyond.
TdLoss huber_loss(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target);
// 0.5 d^2 everywhere (so both losses agree for small errors).
TdLoss squared_loss(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target);

// DQfD's large-margin loss (Hester et al. 2018) on demonstrated transitions: the mean over columns j
// of max_a [Q(a, j) + margin if a != a_j] - Q(a_j, j), which is 0 once the demonstrated action a_j
// leads every other by `margin`. `q` is actions x n; `grad` is d loss / d q, actions x n column-major.
TdLoss large_margin_loss(const Eigen::MatrixXf& q, const Eigen::VectorXi& demo_actions, float margin);

// Linear exploration schedule: `initial` at step 0 falling to `final` at fraction * total steps,
// `final` afterwards (Stable-Baselines3's).
double epsilon_at(long long timesteps, long long total_timesteps, double fraction, double initial,
                  double final_eps);

}  // namespace rdsim::dqn
