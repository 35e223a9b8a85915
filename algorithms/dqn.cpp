// Deep Q-Learning (Mnih et al. 2015) as in the common baselines: experience replay, a target
// network refreshed every target_update_interval env steps (hard copy, or Polyak with tau < 1),
// linear epsilon-greedy exploration, Huber TD loss, optional double Q-learning (van Hasselt et
// al. 2016), optional n-step returns (n_step_returns.hpp), global grad-norm clipping, train_freq
// env steps per env between training phases of gradient_steps minibatch updates, and no learning
// before learning_starts. With
// demonstrations (demonstrations.hpp): a demonstration buffer that is never overwritten, a share of
// every minibatch from it, pre-training on it, and optionally DQfD's large-margin loss.
#include "rdsim/algorithms/dqn.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rdsim/algorithms/transition_step.hpp"
#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/demonstrations.hpp"
#include "rdsim/algorithms/gradient_averaging.hpp"
#include "rdsim/algorithms/hindsight_replay.hpp"
#include "rdsim/algorithms/n_step_returns.hpp"
#include "rdsim/algorithms/observation_normalizer.hpp"
#include "rdsim/policy/policy_program.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/nn/nn.hpp"
#include "memory_footprint.hpp"

namespace rdsim {

namespace dqn {

Eigen::VectorXf td_targets(const Eigen::VectorXf& rewards, const Eigen::VectorXf& terminated,
                           const Eigen::MatrixXf& next_q_target, const Eigen::MatrixXf* next_q_online,
                           float gamma, const Eigen::VectorXf* steps) {
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
  if (!steps) return rewards.array() + gamma * (1.0f - terminated.array()) * next_value.array();
  const Eigen::ArrayXf discount = steps->array().unaryExpr([gamma](float k) { return std::pow(gamma, k); });
  return rewards.array() + discount * (1.0f - terminated.array()) * next_value.array();
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

TdLoss large_margin_loss(const Eigen::MatrixXf& q, const Eigen::VectorXi& demo_actions, float margin) {
  const Eigen::Index n = demo_actions.size();
  TdLoss out;
  out.grad = Eigen::VectorXf::Zero(q.rows() * n);  // actions x n, column-major
  if (n == 0) return out;
  const float inv = 1.0f / static_cast<float>(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const int demo = demo_actions[j];
    Eigen::Index best = 0;
    float best_value = -std::numeric_limits<float>::infinity();
    for (Eigen::Index a = 0; a < q.rows(); ++a) {
      const float v = q(a, j) + (a == demo ? 0.0f : margin);
      if (v > best_value) {
        best_value = v;
        best = a;
      }
    }
    out.loss += (best_value - q(demo, j)) * inv;
    if (best != demo) {
      out.grad[j * q.rows() + best] += inv;
      out.grad[j * q.rows() + demo] -= inv;
    }
  }
  return out;
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

int checked_num_actions(const DqnConfig& config, const Spec& spec, const std::string& where, bool her) {
  if (her) require_goal_env(spec, where);
  if (!spec.action.discrete || spec.action.n <= 0)
    throw Error(where + ": algorithm: \"dqn\" needs a discrete action space, env \"" + spec.env_name +
                "\" has continuous actions (set env.is_discrete to true" +
                (her ? std::string(": reach_goal and push have Discrete(6) effector moves") : " or use ppo/a2c") + ")");
  // A hindsight goal relabels one stored transition; an n-step one would need its n rewards again.
  if (her && config.n_step > 1)
    throw Error(where + ": dqn.n_step: expected 1 with \"her\" (hindsight goals relabel one-step transitions), got " +
                std::to_string(config.n_step));
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
  QNet(const QNet& other) : net_(other.net_->clone()), input_scale_(other.input_scale_), normalizer_(other.normalizer_) {}
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
  // The network's operations (policy_program.hpp).
  void add_ops(PolicyProgram& program) const {
    if (normalizer_)
      normalizer_->add_input_ops(program, input_scale_);
    else
      program.scale(input_scale_);
    if (const auto* cnn = dynamic_cast<const nn::Cnn*>(net_.get()))
      program.cnn(*cnn);
    else
      program.mlp(dynamic_cast<const nn::Mlp&>(*net_));
  }
  // "normalize_observations": the algorithm's normaliser, which outlives this network.
  void normalize_with(const ObservationNormalizer* normalizer) { normalizer_ = normalizer; }

private:
  // network.input_scale (the config parser allows it with vector observations only).
  // Or the standardised observations with normalize_observations.
  const Eigen::MatrixXf& scaled(const Eigen::MatrixXf& x) {
    if (!normalizer_) return scaled_input(x, input_scale_, scaled_input_);
    return normalizer_->network_input(x, input_scale_, scaled_input_);
  }

  std::unique_ptr<nn::Network> net_;
  float input_scale_ = 1.0f;
  const ObservationNormalizer* normalizer_ = nullptr;
  Eigen::MatrixXf scaled_input_;
};

class Dqn final : public Algorithm {
public:
  Dqn(const DqnConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
      const std::string& where, const std::optional<HerConfig>& her)
      : cfg_(config),
        spec_(spec),
        num_actions_(checked_num_actions(config, spec, where, her.has_value())),
        buffer_(config.buffer_size, spec.observation),
        n_step_(config.n_step, config.gamma, spec.observation),
        explore_rng_(Rng::derive(seed, rng_stream::exploration)),
        replay_rng_(Rng::derive(seed, rng_stream::replay_sampling)) {
    Rng init = Rng::derive(seed, rng_stream::network_init);
    q_ = QNet(network, spec, num_actions_, init, where);
    target_ = q_;
    nn::AdamConfig adam;
    adam.lr = static_cast<float>(cfg_.learning_rate);
    optimizer_ = std::make_unique<nn::Adam>(q_.params(), adam);
    if (her) her_.emplace(*her, spec.goal, config.buffer_size);
  }

  std::string name() const override { return "dqn"; }
  // Every learner gradient step averages its gradients over the ranks (train_on).
  bool data_parallel() const override { return true; }
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  // The greedy action: the largest Q-value.
  PolicyProgram policy_program() const override {
    PolicyProgram program;
    program.algorithm = name();
    program.input_size = buffer_.observation_size();
    program.pixels = spec_.observation.type == ObsType::UInt8;
    if (program.pixels) program.image_shape = spec_.observation.shape;
    program.discrete = true;
    program.action_size = 1;
    q_.add_ops(program);
    program.argmax();
    return program;
  }
  void enable_observation_normalization() override {
    normalizer_ = ObservationNormalizer(buffer_.observation_size());
    q_.normalize_with(&normalizer_);
    target_.normalize_with(&normalizer_);
  }
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;
  std::vector<Metrics> learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config, Rng& rng,
                                                 bool pretrain) override;

private:
  struct StepStats {
    double loss = 0, margin = 0, q = 0, norm = 0;
  };
  void collect_step(VecEnv& envs, double epsilon, bool warmup);
  // A minibatch from the replay buffer (and the demonstration buffer, if any), then train_on().
  void gradient_step(StepStats& stats);
  // `count` transitions of the env's replay buffer into batch_: with hindsight goals under "her".
  void sample_env(int count);
  // One gradient step on batch_, whose first `demo_count` columns are demonstrated transitions.
  void train_on(int demo_count, StepStats& stats);

  DqnConfig cfg_;
  Spec spec_;
  int num_actions_;
  ObservationNormalizer normalizer_;  // "normalize_observations" (off by default); q_ and target_ point to it
  QNet q_, target_;
  std::unique_ptr<nn::Adam> optimizer_;
  ReplayBuffer buffer_;
  std::optional<HindsightReplay> her_;  // with a "her" config: which episode each stored transition is in
  NStepReturns n_step_;  // each env's last n_step - 1 steps, until their return is known
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
  // Demonstrations: their own buffer, never overwritten (empty without demonstrations).
  std::unique_ptr<ReplayBuffer> demo_buffer_;
  DemonstrationsConfig demo_cfg_;
  ReplayBatch demo_batch_;
};

void Dqn::collect_step(VecEnv& envs, double epsilon, bool warmup) {
  const int n = envs.size();
  actions_.resize(static_cast<std::size_t>(n));
  // Before learning starts every action is random (the network is untrained anyway).
  const Eigen::MatrixXf* q = nullptr;
  if (!warmup || normalizer_.enabled()) {
    const Eigen::MatrixXf& input = network_input(envs.observations(), obs_);
    if (normalizer_.enabled()) normalizer_.observe(input);
    if (!warmup) q = &q_.infer(input);
  }
  for (int i = 0; i < n; ++i) {
    const bool random = warmup || explore_rng_.uniform() < epsilon;
    const int a = random ? static_cast<int>(explore_rng_.below(static_cast<std::uint64_t>(num_actions_)))
                         : argmax(q->col(i));
    actions_[static_cast<std::size_t>(i)] = Action::discrete(a);
  }
  // The buffer keeps observations in the env's own form (pixels as bytes).
  step_transitions(envs, actions_, prev_obs_, next_obs_,
                   [&](int i, const Observation& obs, const EnvStep& s, const Observation& next) {
                     n_step_.add(i, obs, actions_[static_cast<std::size_t>(i)].index, s.reward, next, s.terminated,
                                 s.done(), buffer_);
                     if (her_) her_->added(buffer_.last_slot(), i, n, s.done());  // one-step: added just now
                   });
  ++env_calls_;
  const long long interval = std::max<long long>(cfg_.target_update_interval / n, 1);
  if (env_calls_ % interval == 0) {
    if (cfg_.tau >= 1.0)
      target_.copy_values_from(q_);
    else
      target_.blend_values_from(q_, static_cast<float>(cfg_.tau));
  }
}

void Dqn::gradient_step(StepStats& stats) {
  const int b = cfg_.batch_size;
  const int demo_count =
      demo_buffer_ ? (buffer_.size() == 0 ? b : static_cast<int>(std::lround(demo_cfg_.demo_fraction * b))) : 0;
  if (demo_count == 0) {
    sample_env(b);
    train_on(0, stats);
    return;
  }
  // Demonstrated transitions first, then the env's: one batch.
  demo_buffer_->sample(demo_count, replay_rng_, demo_batch_);
  if (demo_count < b) sample_env(b - demo_count);
  const int env_count = b - demo_count;
  auto join = [&](Eigen::MatrixXf& env_part, const Eigen::MatrixXf& demo_part) {
    Eigen::MatrixXf joined(demo_part.rows(), b);
    joined.leftCols(demo_count) = demo_part.leftCols(demo_count);
    if (env_count > 0) joined.rightCols(env_count) = env_part.leftCols(env_count);
    env_part = std::move(joined);
  };
  auto join_vector = [&](auto& env_part, const auto& demo_part) {
    std::remove_reference_t<decltype(env_part)> joined(b);
    joined.head(demo_count) = demo_part.head(demo_count);
    if (env_count > 0) joined.tail(env_count) = env_part.head(env_count);
    env_part = std::move(joined);
  };
  join(batch_.observations, demo_batch_.observations);
  join(batch_.next_observations, demo_batch_.next_observations);
  join_vector(batch_.actions, demo_batch_.actions);
  join_vector(batch_.rewards, demo_batch_.rewards);
  join_vector(batch_.terminated, demo_batch_.terminated);
  join_vector(batch_.steps, demo_batch_.steps);
  train_on(demo_count, stats);
}

void Dqn::sample_env(int count) {
  if (her_)
    her_->sample(buffer_, count, replay_rng_, batch_);
  else
    buffer_.sample(count, replay_rng_, batch_);
}

void Dqn::train_on(int demo_count, StepStats& stats) {
  const Eigen::MatrixXf& next_q_target = target_.infer(batch_.next_observations);
  const Eigen::MatrixXf* next_q_online = cfg_.double_q ? &q_.infer(batch_.next_observations) : nullptr;
  const Eigen::VectorXf targets = dqn::td_targets(batch_.rewards, batch_.terminated, next_q_target, next_q_online,
                                                  static_cast<float>(cfg_.gamma), cfg_.n_step > 1 ? &batch_.steps : nullptr);

  const Eigen::MatrixXf& q = q_.forward(batch_.observations);
  const int b = static_cast<int>(batch_.actions.size());
  Eigen::VectorXf chosen(b);
  for (int j = 0; j < b; ++j) chosen[j] = q(batch_.actions[j], j);
  const dqn::TdLoss loss = cfg_.huber ? dqn::huber_loss(chosen, targets) : dqn::squared_loss(chosen, targets);

  // Only the Q-value of the action taken receives the TD gradient.
  grad_q_.setZero(num_actions_, b);
  for (int j = 0; j < b; ++j) grad_q_(batch_.actions[j], j) = loss.grad[j];
  if (demo_count > 0 && demo_cfg_.large_margin) {
    const dqn::TdLoss margin = dqn::large_margin_loss(q.leftCols(demo_count), batch_.actions.head(demo_count),
                                                      static_cast<float>(demo_cfg_.margin));
    const float w = static_cast<float>(demo_cfg_.margin_weight);
    grad_q_.leftCols(demo_count) += w * Eigen::Map<const Eigen::MatrixXf>(margin.grad.data(), num_actions_, demo_count);
    stats.margin += margin.loss;
  }
  q_.zero_grad();
  q_.backward(grad_q_);
  const nn::ParamList params = optimizer_->params();
  average_gradients(communicator(), params, gradient_buffer_);
  stats.norm += cfg_.max_grad_norm > 0 ? nn::clip_grad_norm(params, static_cast<float>(cfg_.max_grad_norm))
                                       : nn::global_grad_norm(params);
  optimizer_->step();
  ++gradient_steps_;
  stats.loss += loss.loss;
  stats.q += chosen.cast<double>().mean();
}

std::vector<Metrics> Dqn::learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config, Rng& rng,
                                                    bool pretrain) {
  long long transitions = 0;
  for (const DemoEpisode& e : demos.episodes) transitions += e.steps();
  if (transitions == 0) throw Error(demos.path + ": holds no demonstrated step to learn from");
  demo_cfg_ = config;
  demo_buffer_ = std::make_unique<ReplayBuffer>(transitions, spec_.observation);
  for (const DemoEpisode& e : demos.episodes) {
    for (int t = 0; t < e.steps(); ++t) {
      const auto i = static_cast<std::size_t>(t);
      // The last step of an episode the env did not end (truncated, or stopped by a person) bootstraps.
      const bool terminated = e.terminated && t == e.steps() - 1;
      demo_buffer_->add(e.observations[i], e.actions[i].index, e.rewards[i], e.observations[i + 1], terminated);
    }
  }
  std::vector<Metrics> rows;
  if (!pretrain) return rows;
  // Pre-training on the demonstrations alone (DQfD's first phase), the target refreshed every epoch.
  const long long steps_per_epoch = std::max<long long>(1, (transitions + cfg_.batch_size - 1) / cfg_.batch_size);
  optimizer_->set_learning_rate(static_cast<float>(config.learning_rate));
  for (int epoch = 1; epoch <= config.bc_epochs; ++epoch) {
    StepStats stats;
    for (long long k = 0; k < steps_per_epoch; ++k) {
      demo_buffer_->sample(cfg_.batch_size, rng, batch_);
      train_on(cfg_.batch_size, stats);
    }
    target_.copy_values_from(q_);
    const double m = static_cast<double>(steps_per_epoch);
    rows.push_back({{"epoch", epoch}, {"td_loss", stats.loss / m}, {"margin_loss", stats.margin / m}, {"q_mean", stats.q / m}});
  }
  gradient_steps_ = 0;  // the training schedule counts RL steps only
  return rows;
}

Metrics Dqn::update(VecEnv& envs, const TrainProgress& progress) {
  const int n = envs.size();
  const long long calls = progress.phase_steps(cfg_.train_freq, n);
  double epsilon = 0.0;
  for (long long c = 0; c < calls; ++c) {
    epsilon = dqn::epsilon_at(envs.timesteps(), progress.total_timesteps, cfg_.exploration_fraction,
                              cfg_.exploration_initial_eps, cfg_.exploration_final_eps);
    collect_step(envs, epsilon, envs.timesteps() < cfg_.learning_starts);
  }

  const double lr = cfg_.anneal_lr ? cfg_.learning_rate * progress.remaining(envs.timesteps()) : cfg_.learning_rate;
  optimizer_->set_learning_rate(static_cast<float>(lr));
  StepStats stats;
  int trained = 0;
  if (envs.timesteps() > cfg_.learning_starts) {
    for (; trained < cfg_.gradient_steps; ++trained) gradient_step(stats);
  }
  const double m = std::max(trained, 1);
  Metrics metrics = {{"loss", stats.loss / m},
          {"q_mean", stats.q / m},
          {"grad_norm", stats.norm / m},
          {"epsilon", epsilon},
          {"learning_rate", lr},
          {"gradient_steps", static_cast<double>(gradient_steps_)},
          {"buffer_size", static_cast<double>(buffer_.size())}};
  if (her_) metrics.push_back({"her_relabelable", static_cast<double>(her_->relabelable())});
  if (demo_buffer_ && demo_cfg_.large_margin) metrics.push_back({"margin_loss", stats.margin / m});
  // The next update's inputs: the statistics with this one's observations.
  if (normalizer_.enabled()) normalizer_.refresh(communicator());
  return metrics;
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
  normalizer_.save(out, training_state);
  if (!training_state) return;
  nn::save_params(const_cast<QNet&>(target_).params(), out);
  optimizer_->save_state(out);
  write_string(out, rng_to_bytes(explore_rng_));
  write_string(out, rng_to_bytes(replay_rng_));
  write_u64(out, static_cast<std::uint64_t>(env_calls_));
  write_u64(out, static_cast<std::uint64_t>(gradient_steps_));
  buffer_.save(out);
  if (cfg_.n_step > 1) n_step_.save(out);  // absent with one-step returns: older checkpoints load
  if (her_) her_->save(out, buffer_.size());
}

void Dqn::load(std::istream& in, bool training_state, const std::string& source) {
  nn::load_params(q_.params(), in, source);
  normalizer_.load(in, training_state, source);
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
  if (cfg_.n_step > 1) n_step_.load(in, source);
  if (her_) her_->load(in, buffer_.size(), source);
  if (buffer_.size() > 0 && buffer_.largest_action() >= num_actions_)
    throw Error(source + ": replay buffer holds an action outside the env's " + std::to_string(num_actions_) +
                " (damaged file?)");
}

}  // namespace

std::unique_ptr<Algorithm> make_dqn(const DqnConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where, const std::optional<HerConfig>& her) {
  return std::make_unique<Dqn>(config, network, seed, spec, where, her);
}

// Online and target Q networks with Adam state, the replay buffer (pixels as bytes), training passes.
void estimate_memory(const DqnConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  using memory::kFloat;
  const memory::Footprint f = memory::q_network(c.network, spec, c.source);
  const double obs = observation_input_size(spec.observation);
  const double obs_bytes = spec.observation.type == ObsType::UInt8 ? obs : obs * kFloat;
  // Online and target networks, gradients, two Adam moments.
  e.add(std::string("Q networks, gradients and optimiser state (") + memory::network_keys(spec) + ")", 5.0 * kFloat * f.params);
  const double replay = static_cast<double>(p.buffer_size) * (2.0 * obs_bytes + 4.0 * kFloat);
  e.add("replay buffer (dqn.buffer_size)", replay);
  e.add("training activations (dqn.batch_size)",
        2.0 * p.batch_size * (3.0 * f.activations + 2.0 * obs) * kFloat + num_envs * (f.activations + obs) * kFloat);
  e.add("checkpoint writing (in-memory copies of the networks and the replay buffer)",
        2.0 * (4.0 * kFloat * f.params + replay));
}

}  // namespace rdsim
