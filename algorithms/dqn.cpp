// Deep Q-Learning (Mnih et al. 2015) as in the common baselines: experience replay, a target
// network refreshed every target_update_interval env steps (hard copy, or Polyak with tau < 1),
// linear epsilon-greedy exploration, Huber TD loss, optional double Q-learning (van Hasselt et
// al. 2016), global grad-norm clipping, train_freq env steps per env between training phases
// of gradient_steps minibatch updates, and no learning before learning_starts.
#include "rdsim/algorithms/dqn.hpp"

#include <algorithm>
#include <cmath>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/gradient_averaging.hpp"
#include "rdsim/algorithms/observation_batch.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/algorithms/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/nn/nn.hpp"

namespace rdsim {

namespace dqn {

Eigen::VectorXf td_targets(const Eigen::VectorXf& rewards, const Eigen::VectorXf& terminated,
                           const Eigen::MatrixXf& next_q_target, const Eigen::MatrixXf* next_q_online,
                           float gamma) {
  const Eigen::Index batch = rewards.size();
  Eigen::VectorXf next_value(batch);
  for (Eigen::Index j = 0; j < batch; ++j) {
    if (next_q_online) {
      Eigen::Index best;
      next_q_online->col(j).maxCoeff(&best);
      next_value[j] = next_q_target(best, j);
    } else {
      next_value[j] = next_q_target.col(j).maxCoeff();
    }
  }
  return rewards.array() + gamma * (1.0f - terminated.array()) * next_value.array();
}

TdLoss huber_loss(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target) {
  const Eigen::ArrayXf d = (prediction - target).array();
  const Eigen::ArrayXf a = d.abs();
  const float inv_b = 1.0f / static_cast<float>(d.size());
  TdLoss out;
  out.loss = (a <= 1.0f).select(0.5f * d.square(), a - 0.5f).sum() * inv_b;
  out.grad = (d.cwiseMax(-1.0f).cwiseMin(1.0f) * inv_b).matrix();
  return out;
}

TdLoss squared_loss(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target) {
  const Eigen::VectorXf d = prediction - target;
  const float inv_b = 1.0f / static_cast<float>(d.size());
  return {0.5f * d.squaredNorm() * inv_b, d * inv_b};
}

double epsilon_at(long long timesteps, long long total_timesteps, double fraction, double initial,
                  double final_eps) {
  const double span = fraction * static_cast<double>(total_timesteps);
  if (span <= 0.0) return final_eps;
  const double progress = std::min(1.0, static_cast<double>(timesteps) / span);
  return initial + progress * (final_eps - initial);
}

}  // namespace dqn

namespace {

int checked_num_actions(const DqnConfig&, const Spec& spec, const std::string& where) {
  if (!spec.action.discrete || spec.action.n <= 0)
    throw Error(where + ": algorithm: \"dqn\" needs a discrete action space, env \"" + spec.env_name +
                "\" has continuous actions (set env.is_discrete to true or use ppo/a2c)");
  return spec.action.n;
}

int argmax(const Eigen::Ref<const Eigen::VectorXf>& q) {
  Eigen::Index best;
  q.maxCoeff(&best);
  return static_cast<int>(best);
}

// The Q-network: an MLP on vector observations (times network.input_scale), a CNN (network.cnn)
// on pixel observations.
class QNet {
public:
  QNet() = default;
  QNet(const NetworkConfig& network, const Spec& spec, int num_actions, Rng& init, const std::string& where) {
    if (is_image_space(spec.observation)) {
      const std::string at = where + ": network.cnn";
      net_ = std::make_unique<nn::Cnn>(make_cnn(cnn_shape(network.cnn, spec.observation, num_actions, at), 1.0f, init, at));
    } else {
      const nn::MlpShape shape{observation_input_size(spec.observation), network.hidden_sizes, num_actions,
                               nn::activation_from_string(network.activation, where + ": network.activation")};
      net_ = std::make_unique<nn::Mlp>(shape, 1.0f, init);
      input_scale_ = static_cast<float>(network.input_scale);
    }
  }
  QNet(const QNet& other) : net_(other.net_->clone()), input_scale_(other.input_scale_) {}
  QNet& operator=(const QNet& other) {
    if (this != &other) *this = QNet(other);
    return *this;
  }
  QNet(QNet&&) = default;
  QNet& operator=(QNet&&) = default;

  const Eigen::MatrixXf& infer(const Eigen::MatrixXf& x) { return net_->infer(scaled(x)); }
  const Eigen::MatrixXf& forward(const Eigen::MatrixXf& x) { return net_->forward(scaled(x)); }
  void backward(const Eigen::MatrixXf& grad) { net_->backward(grad, false); }
  void zero_grad() { net_->zero_grad(); }
  nn::ParamList params() { return net_->params(); }
  void copy_values_from(const QNet& other) { net_->copy_values_from(*other.net_); }
  void blend_values_from(const QNet& other, float tau) { net_->blend_values_from(*other.net_, tau); }

private:
  // network.input_scale (the config parser allows it with vector observations only).
  const Eigen::MatrixXf& scaled(const Eigen::MatrixXf& x) { return scaled_input(x, input_scale_, scaled_input_); }

  std::unique_ptr<nn::Network> net_;
  float input_scale_ = 1.0f;
  Eigen::MatrixXf scaled_input_;
};

class Dqn final : public Algorithm {
public:
  Dqn(const DqnConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
      const std::string& where)
      : cfg_(config),
        spec_(spec),
        num_actions_(checked_num_actions(config, spec, where)),
        buffer_(config.buffer_size, spec.observation),
        explore_rng_(Rng::derive(seed, rng_stream::exploration)),
        replay_rng_(Rng::derive(seed, rng_stream::replay_sampling)) {
    Rng init = Rng::derive(seed, rng_stream::network_init);
    q_ = QNet(network, spec, num_actions_, init, where);
    target_ = q_;
    nn::AdamConfig adam;
    adam.lr = static_cast<float>(cfg_.learning_rate);
    optimizer_ = std::make_unique<nn::Adam>(q_.params(), adam);
  }

  std::string name() const override { return "dqn"; }
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;

private:
  void collect_step(VecEnv& envs, double epsilon, bool warmup);
  void gradient_step(double& loss_sum, double& q_sum, double& norm_sum);

  DqnConfig cfg_;
  Spec spec_;
  int num_actions_;
  QNet q_, target_;
  std::unique_ptr<nn::Adam> optimizer_;
  ReplayBuffer buffer_;
  Rng explore_rng_, replay_rng_;
  long long env_calls_ = 0;       // VecEnv::step calls: the clock of target updates
  long long gradient_steps_ = 0;  // since the start of training
  // scratch, reused so the hot loop does not allocate
  Eigen::MatrixXf obs_, grad_q_;
  std::vector<Observation> prev_obs_;
  Observation next_obs_;
  std::vector<float> gradient_buffer_;
  std::vector<Action> actions_;
  ReplayBatch batch_;
};

void Dqn::collect_step(VecEnv& envs, double epsilon, bool warmup) {
  const int n = envs.size();
  actions_.resize(static_cast<std::size_t>(n));
  // Before learning starts every action is random (the network is untrained anyway).
  const Eigen::MatrixXf* q = warmup ? nullptr : &q_.infer(network_input(envs.observations(), obs_));
  for (int i = 0; i < n; ++i) {
    const bool random = warmup || explore_rng_.uniform() < epsilon;
    const int a = random ? static_cast<int>(explore_rng_.below(static_cast<std::uint64_t>(num_actions_)))
                         : argmax(q->col(i));
    actions_[static_cast<std::size_t>(i)] = Action::discrete(a);
  }
  // The buffer keeps observations in the env's own form (pixels as bytes), so keep a copy of
  // the ones the actions were chosen from: step() replaces them. (Copies reuse their storage.)
  prev_obs_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) envs.observations().copy_to(i, prev_obs_[static_cast<std::size_t>(i)]);
  const std::vector<EnvStep>& steps = envs.step(actions_);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const EnvStep& s = steps[k];
    // After an episode ends the env has been reset: the transition's next state is the final one.
    if (!s.done()) envs.observations().copy_to(i, next_obs_);
    buffer_.add(prev_obs_[k], actions_[k].index, s.reward, s.done() ? s.final_observation : next_obs_, s.terminated);
  }
  ++env_calls_;
  const long long interval = std::max<long long>(cfg_.target_update_interval / n, 1);
  if (env_calls_ % interval == 0) {
    if (cfg_.tau >= 1.0)
      target_.copy_values_from(q_);
    else
      target_.blend_values_from(q_, static_cast<float>(cfg_.tau));
  }
}

void Dqn::gradient_step(double& loss_sum, double& q_sum, double& norm_sum) {
  buffer_.sample(cfg_.batch_size, replay_rng_, batch_);
  const Eigen::MatrixXf& next_q_target = target_.infer(batch_.next_observations);
  const Eigen::MatrixXf* next_q_online = cfg_.double_q ? &q_.infer(batch_.next_observations) : nullptr;
  const Eigen::VectorXf targets =
      dqn::td_targets(batch_.rewards, batch_.terminated, next_q_target, next_q_online, static_cast<float>(cfg_.gamma));

  const Eigen::MatrixXf& q = q_.forward(batch_.observations);
  const int b = cfg_.batch_size;
  Eigen::VectorXf chosen(b);
  for (int j = 0; j < b; ++j) chosen[j] = q(batch_.actions[j], j);
  const dqn::TdLoss loss = cfg_.huber ? dqn::huber_loss(chosen, targets) : dqn::squared_loss(chosen, targets);

  // Only the Q-value of the action taken receives a gradient.
  grad_q_.setZero(num_actions_, b);
  for (int j = 0; j < b; ++j) grad_q_(batch_.actions[j], j) = loss.grad[j];
  q_.zero_grad();
  q_.backward(grad_q_);
  const nn::ParamList params = optimizer_->params();
  average_gradients(communicator(), params, gradient_buffer_);
  norm_sum += cfg_.max_grad_norm > 0 ? nn::clip_grad_norm(params, static_cast<float>(cfg_.max_grad_norm))
                                     : nn::global_grad_norm(params);
  optimizer_->step();
  ++gradient_steps_;
  loss_sum += loss.loss;
  q_sum += chosen.cast<double>().mean();
}

Metrics Dqn::update(VecEnv& envs, const TrainProgress& progress) {
  const int n = envs.size();
  // The last phase stops at the run's goal instead of overshooting by up to train_freq steps.
  const long long left = progress.total_timesteps - envs.timesteps();
  const long long calls = left > 0 ? std::min<long long>(cfg_.train_freq, (left + n - 1) / n) : cfg_.train_freq;
  double epsilon = 0.0;
  for (long long c = 0; c < calls; ++c) {
    epsilon = dqn::epsilon_at(envs.timesteps(), progress.total_timesteps, cfg_.exploration_fraction,
                              cfg_.exploration_initial_eps, cfg_.exploration_final_eps);
    collect_step(envs, epsilon, envs.timesteps() < cfg_.learning_starts);
  }

  const double lr = cfg_.anneal_lr ? cfg_.learning_rate * progress.remaining(envs.timesteps()) : cfg_.learning_rate;
  optimizer_->set_learning_rate(static_cast<float>(lr));
  double loss_sum = 0, q_sum = 0, norm_sum = 0;
  int trained = 0;
  if (envs.timesteps() > cfg_.learning_starts) {
    for (; trained < cfg_.gradient_steps; ++trained) gradient_step(loss_sum, q_sum, norm_sum);
  }
  const double m = std::max(trained, 1);
  return {{"loss", loss_sum / m},
          {"q_mean", q_sum / m},
          {"grad_norm", norm_sum / m},
          {"epsilon", epsilon},
          {"learning_rate", lr},
          {"gradient_steps", static_cast<double>(gradient_steps_)},
          {"buffer_size", static_cast<double>(buffer_.size())}};
}

Action Dqn::act(const Observation& observation, bool deterministic, Rng& rng) {
  // Stochastic acting (replay --stochastic) is epsilon-greedy with the final exploration rate.
  if (!deterministic && rng.uniform() < cfg_.exploration_final_eps)
    return Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(num_actions_))));
  obs_.resize(buffer_.observation_size(), 1);
  encode_observation(observation, spec_.observation, obs_.col(0));
  return Action::discrete(argmax(q_.infer(obs_).col(0)));
}

void Dqn::save(std::ostream& out, bool training_state) const {
  QNet& q = const_cast<QNet&>(q_);  // params() hands out mutable views; saving only reads them
  nn::save_params(q.params(), out);
  if (!training_state) return;
  nn::save_params(const_cast<QNet&>(target_).params(), out);
  optimizer_->save_state(out);
  write_string(out, rng_to_bytes(explore_rng_));
  write_string(out, rng_to_bytes(replay_rng_));
  write_u64(out, static_cast<std::uint64_t>(env_calls_));
  write_u64(out, static_cast<std::uint64_t>(gradient_steps_));
  buffer_.save(out);
}

void Dqn::load(std::istream& in, bool training_state, const std::string& source) {
  nn::load_params(q_.params(), in, source);
  if (!training_state) {
    target_.copy_values_from(q_);
    return;
  }
  nn::load_params(target_.params(), in, source);
  optimizer_->load_state(in, source);
  explore_rng_ = rng_from_bytes(read_string(in, source), source);
  replay_rng_ = rng_from_bytes(read_string(in, source), source);
  const std::uint64_t env_calls = read_u64(in, source), gradient_steps = read_u64(in, source);
  if (env_calls > (1ull << 50) || gradient_steps > (1ull << 50))
    throw Error(source + ": checkpoint holds DQN counters out of range (damaged file?)");
  env_calls_ = static_cast<long long>(env_calls);
  gradient_steps_ = static_cast<long long>(gradient_steps);
  buffer_.load(in, source);
  if (buffer_.size() > 0 && buffer_.largest_action() >= num_actions_)
    throw Error(source + ": replay buffer holds an action outside the env's " + std::to_string(num_actions_) +
                " (damaged file?)");
}

}  // namespace

std::unique_ptr<Algorithm> make_dqn(const DqnConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where) {
  return std::make_unique<Dqn>(config, network, seed, spec, where);
}

}  // namespace rdsim
