// TD3 (Fujimoto et al. 2018) as in Stable-Baselines3: a deterministic tanh actor, twin critics
// whose minimum makes the TD target (clipped double Q-learning), target policy smoothing
// (clipped Gaussian noise on the target action), and delayed actor and target updates
// (policy_delay critic steps per actor step, targets Polyak-averaged then). Exploration adds
// Gaussian or Ornstein-Uhlenbeck noise to the actor's action. DDPG (Lillicrap et al. 2016) is the
// same algorithm with one critic, no smoothing and no delay. Actions live in [-1, 1] inside the
// algorithm and are rescaled to the env's Box (OffPolicy).
#include "rdsim/algorithms/td3.hpp"

#include <algorithm>
#include <cmath>

#include "rdsim/algorithms/off_policy.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/nn/nn.hpp"
#include "rdsim/nn/serialize.hpp"
#include "memory_footprint.hpp"

namespace rdsim {
namespace {

constexpr float hidden_gain = 1.41421356f;
constexpr float actor_gain = 0.01f;  // near-zero first actions, away from tanh saturation
constexpr float critic_gain = 1.0f;

class Td3 final : public OffPolicy {
public:
  Td3(const Td3Config& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
      const std::string& name, const std::string& where, const std::optional<HerConfig>& her)
      : OffPolicy(config, network, seed, spec, name, where, her),
        cfg_(config),
        name_(name),
        critics_(config.twin_q ? 2 : 1),
        noise_rng_(Rng::derive(seed, rng_stream::training_noise)) {
    const nn::Activation act = nn::activation_from_string(network.activation, where + ": network.activation");
    Rng init = Rng::derive(seed, rng_stream::network_init);
    actor_ = nn::Mlp({observation_size_, network.hidden_sizes, action_dim_, act}, actor_gain, init, hidden_gain);
    actor_target_ = actor_;
    const nn::MlpShape critic{observation_size_ + action_dim_, network.hidden_sizes, 1, act};
    for (int i = 0; i < critics_; ++i) {
      q_[i] = nn::Mlp(critic, critic_gain, init, hidden_gain);
      q_target_[i] = q_[i];
    }
    nn::AdamConfig adam;
    adam.lr = static_cast<float>(cfg_.learning_rate);
    actor_optimizer_ = std::make_unique<nn::Adam>(actor_.params(), adam);
    nn::ParamList critic_params;
    for (int i = 0; i < critics_; ++i)
      for (const nn::Param& p : q_[i].params()) critic_params.push_back(p);
    critic_optimizer_ = std::make_unique<nn::Adam>(critic_params, adam);
  }

  std::string name() const override { return name_; }

protected:
  void policy(const Eigen::MatrixXf& obs, bool deterministic, Rng& rng, Eigen::MatrixXf& actions) override;
  // tanh of the actor's output, to the Box (actor_action, env_action).
  PolicyProgram policy_program() const override {
    PolicyProgram program = policy_program_start();
    program.mlp(actor_);
    program.activate(nn::Activation::Tanh);
    add_env_action_ops(program);
    return program;
  }
  void on_episode_end(int env) override {
    if (env < ou_state_.cols()) ou_state_.col(env).setZero();
  }
  Metrics train(int steps, const TrainProgress& progress) override;
  nn::ParamList acting_params() override { return actor_.params(); }
  nn::ParamList other_params() override {
    nn::ParamList list = actor_target_.params();
    for (int i = 0; i < critics_; ++i)
      for (nn::Mlp* net : {&q_[i], &q_target_[i]})
        for (const nn::Param& p : net->params()) list.push_back(p);
    return list;
  }
  void save_training(std::ostream& out) const override;
  void load_training(std::istream& in, const std::string& source) override;

private:
  // a = tanh(actor(s)), the deterministic action in [-1, 1].
  Eigen::MatrixXf actor_action(nn::Mlp& net, const Eigen::MatrixXf& obs, bool training) {
    const Eigen::MatrixXf& in = actor_input(obs, input_);
    return (training ? net.forward(in) : net.infer(in)).array().tanh().matrix();
  }
  void gradient_step(double* sums);

  Td3Config cfg_;
  std::string name_;
  int critics_;
  Rng noise_rng_;
  nn::Mlp actor_, actor_target_;
  nn::Mlp q_[2], q_target_[2];
  std::unique_ptr<nn::Adam> actor_optimizer_, critic_optimizer_;
  Eigen::MatrixXf ou_state_;  // action_dim x envs: Ornstein-Uhlenbeck noise of each env
  long long updates_ = 0;     // critic updates (the delay clock)
  double last_actor_loss_ = 0.0;
  ReplayBatch batch_;
  Eigen::MatrixXf input_, critic_in_;
};

void Td3::policy(const Eigen::MatrixXf& obs, bool deterministic, Rng& rng, Eigen::MatrixXf& actions) {
  actions = actor_action(actor_, obs, false);
  if (deterministic || cfg_.action_noise == "none") return;
  const auto sigma = static_cast<float>(cfg_.action_noise_std);
  if (cfg_.action_noise == "normal") {
    for (Eigen::Index k = 0; k < actions.size(); ++k) actions.data()[k] += sigma * static_cast<float>(rng.normal());
  } else {
    // x += theta (0 - x) dt + sigma sqrt(dt) N(0, 1), one process per env (reset at episode ends).
    if (ou_state_.rows() != actions.rows() || ou_state_.cols() != actions.cols()) ou_state_.setZero(actions.rows(), actions.cols());
    const auto theta = static_cast<float>(cfg_.ou_theta), dt = static_cast<float>(cfg_.ou_dt);
    const float scale = sigma * std::sqrt(dt);
    for (Eigen::Index k = 0; k < actions.size(); ++k) {
      float& x = ou_state_.data()[k];
      x += -theta * x * dt + scale * static_cast<float>(rng.normal());
      actions.data()[k] += x;
    }
  }
  actions = actions.cwiseMax(-1.0f).cwiseMin(1.0f);
}

// One critic update, and every policy_delay-th time an actor and target update.
// sums: critic loss, actor loss, mean Q, cloning loss, actor updates.
void Td3::gradient_step(double* sums) {
  const int demos = sample_batch(batch_);
  const int b = cfg_.batch_size;
  const float inv_b = 1.0f / static_cast<float>(b);

  // TD targets from the target actor and critics; smoothing noise on a' (TD3).
  Eigen::MatrixXf next_a = actor_action(actor_target_, batch_.next_observations, false);
  if (cfg_.target_policy_noise > 0.0) {
    const auto sigma = static_cast<float>(cfg_.target_policy_noise), clip = static_cast<float>(cfg_.target_noise_clip);
    for (Eigen::Index k = 0; k < next_a.size(); ++k)
      next_a.data()[k] += std::clamp(sigma * static_cast<float>(noise_rng_.normal()), -clip, clip);
    next_a = next_a.cwiseMax(-1.0f).cwiseMin(1.0f);
  }
  const Eigen::MatrixXf& next_in = critic_input(batch_.next_observations, next_a, critic_in_);
  // The critics' passes are independent: side by side on the learner's threads (nn/gemm.hpp), each
  // writing only its own network and outputs, so the bits do not depend on the thread count.
  Eigen::RowVectorXf target_q[2];
  nn::run_side_by_side(critics_, [&](int i) { target_q[i] = q_target_[i].infer(next_in).row(0); });
  Eigen::VectorXf next_q = target_q[0].transpose();
  if (critics_ == 2) next_q = next_q.cwiseMin(target_q[1].transpose());
  const Eigen::VectorXf y =
      batch_.rewards.array() + static_cast<float>(cfg_.gamma) * (1.0f - batch_.terminated.array()) * next_q.array();

  // Critics: loss sum_i mean((Q_i(s, a) - y)^2).
  const Eigen::MatrixXf& in = critic_input(batch_.observations, batch_.action_values, critic_in_);
  Eigen::RowVectorXf values[2];
  double losses[2];
  nn::run_side_by_side(critics_, [&](int i) {
    q_[i].zero_grad();
    values[i] = q_[i].forward(in).row(0);
    const Eigen::RowVectorXf d = values[i] - y.transpose();
    losses[i] = d.cast<double>().squaredNorm() / b;
    q_[i].backward(2.0f * inv_b * d, false);
  });
  double critic_loss = 0.0, q_mean = 0.0;
  const Eigen::RowVectorXf& q_stored = values[0];  // Q_1 of the stored actions (the demonstrations' Q-filter)
  for (int i = 0; i < critics_; ++i) {  // summed in critic order, as on one thread
    critic_loss += losses[i];
    q_mean += values[i].cast<double>().mean() / critics_;
  }
  average_gradients(critic_optimizer_->params());
  critic_optimizer_->step();
  ++updates_;

  // Delayed actor update: loss -mean(Q_1(s, actor(s))), then all targets move (Polyak).
  if (updates_ % cfg_.policy_delay == 0) {
    const Eigen::MatrixXf a = actor_action(actor_, batch_.observations, true);
    const Eigen::MatrixXf& pi_in = critic_input(batch_.observations, a, critic_in_);
    const Eigen::RowVectorXf q_policy = q_[0].forward(pi_in).row(0);
    last_actor_loss_ = -q_policy.cast<double>().mean();
    Eigen::MatrixXf d_in = q_[0].input_gradient(Eigen::MatrixXf::Constant(1, b, -inv_b));  // Q_1 is not trained by this loss
    // Demonstrated columns: the Q-filtered cloning term pulls the actor's actions towards them.
    sums[3] += clone_demonstrations(demos, a, batch_.action_values, q_stored, q_policy, d_in.bottomRows(action_dim_));
    sums[4] += 1.0;  // actor updates
    // Through the tanh: d a / d output = 1 - a^2.
    const Eigen::MatrixXf d_out = (d_in.bottomRows(action_dim_).array() * (1.0f - a.array().square())).matrix();
    actor_.zero_grad();
    actor_.backward(d_out, false);
    average_gradients(actor_optimizer_->params());
    actor_optimizer_->step();
    const auto tau = static_cast<float>(cfg_.tau);
    actor_target_.blend_values_from(actor_, tau);
    for (int i = 0; i < critics_; ++i) q_target_[i].blend_values_from(q_[i], tau);
  }
  sums[0] += critic_loss;
  sums[1] += last_actor_loss_;
  sums[2] += q_mean;
}

Metrics Td3::train(int steps, const TrainProgress& /*progress*/) {
  double sums[5] = {0, 0, 0, 0, 0};  // ..., cloning loss and actor updates (the delayed ones only)
  for (int k = 0; k < steps; ++k) gradient_step(sums);
  const double m = std::max(steps, 1);
  Metrics metrics{{"critic_loss", sums[0] / m}, {"actor_loss", sums[1] / m}, {"q_mean", sums[2] / m}};
  if (has_demonstrations()) metrics.emplace_back("bc_loss", sums[3] / std::max(sums[4], 1.0));
  return metrics;
}

void Td3::save_training(std::ostream& out) const {
  auto& self = const_cast<Td3&>(*this);  // params() hands out mutable views; saving only reads them
  nn::save_params(self.actor_target_.params(), out);
  for (int i = 0; i < critics_; ++i) {
    nn::save_params(self.q_[i].params(), out);
    nn::save_params(self.q_target_[i].params(), out);
  }
  actor_optimizer_->save_state(out);
  critic_optimizer_->save_state(out);
  write_string(out, rng_to_bytes(noise_rng_));
  write_u64(out, static_cast<std::uint64_t>(updates_));
  write_f64(out, last_actor_loss_);
  nn::write_matrix(out, ou_state_);
}

void Td3::load_training(std::istream& in, const std::string& source) {
  nn::load_params(actor_target_.params(), in, source);
  for (int i = 0; i < critics_; ++i) {
    nn::load_params(q_[i].params(), in, source);
    nn::load_params(q_target_[i].params(), in, source);
  }
  actor_optimizer_->load_state(in, source);
  critic_optimizer_->load_state(in, source);
  noise_rng_ = rng_from_bytes(read_string(in, source), source);
  const std::uint64_t updates = read_u64(in, source);
  if (updates > (1ull << 50)) throw Error(source + ": checkpoint holds an update count out of range (damaged file?)");
  updates_ = static_cast<long long>(updates);
  last_actor_loss_ = read_f64(in, source);
  const std::uint32_t rows = read_u32(in, source), cols = read_u32(in, source);
  if (rows != 0 && rows != static_cast<std::uint32_t>(action_dim_)) throw Error(source + ": damaged exploration noise state");
  if (cols > 4096) throw Error(source + ": damaged exploration noise state");
  ou_state_.resize(rows, cols);
  read_bytes(in, ou_state_.data(), static_cast<std::size_t>(ou_state_.size()) * 4, source);
  if (!std::isfinite(last_actor_loss_) || !ou_state_.allFinite()) throw Error(source + ": damaged exploration noise state");
}

}  // namespace

std::unique_ptr<Algorithm> make_td3(const Td3Config& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where, const std::optional<HerConfig>& her) {
  return std::make_unique<Td3>(config, network, seed, spec, "td3", where, her);
}

std::unique_ptr<Algorithm> make_ddpg(const DdpgConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                     const Spec& spec, const std::string& where, const std::optional<HerConfig>& her) {
  return std::make_unique<Td3>(config, network, seed, spec, "ddpg", where, her);
}

// A deterministic actor with its target, two critics (one for DDPG: counted as two) and their targets.
void estimate_memory(const Td3Config& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  memory::actor_critics(c.network, spec, num_envs, p.buffer_size, p.batch_size, spec.action.dim(), true, "td3", e);
}

void estimate_memory(const DdpgConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  memory::actor_critics(c.network, spec, num_envs, p.buffer_size, p.batch_size, spec.action.dim(), true, "ddpg", e);
}

}  // namespace rdsim
