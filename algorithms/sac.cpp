// Soft actor-critic (Haarnoja et al. 2018, "SAC algorithms and applications") as in
// Stable-Baselines3: a tanh-squashed Gaussian actor, twin Q critics with Polyak-averaged targets,
// the clipped double-Q soft target, and automatic tuning of the entropy coefficient alpha
// towards a target entropy. Off-policy: transitions go to a replay buffer (OffPolicy), each
// gradient step learns from a uniform minibatch. Actions live in [-1, 1] inside the algorithm
// and are rescaled to the env's Box.
#include "rdsim/algorithms/sac.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rdsim/algorithms/off_policy.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/nn/nn.hpp"
#include "memory_footprint.hpp"

namespace rdsim {

namespace sac {

Eigen::VectorXf soft_td_targets(const Eigen::VectorXf& rewards, const Eigen::VectorXf& terminated,
                                const Eigen::VectorXf& next_q_min, const Eigen::VectorXf& next_log_probs, float alpha,
                                float gamma) {
  return rewards.array() + gamma * (1.0f - terminated.array()) * (next_q_min.array() - alpha * next_log_probs.array());
}

}  // namespace sac

namespace {

constexpr float hidden_gain = 1.41421356f;  // sqrt(2) for ReLU/tanh hidden layers
constexpr float actor_gain = 0.01f;         // near-zero means and log-stds: std about 1 at first
constexpr float critic_gain = 1.0f;

// Standard-normal noise, drawn column by column.
void draw_normal(Eigen::MatrixXf& out, int rows, int cols, Rng& rng) {
  out.resize(rows, cols);
  for (Eigen::Index k = 0; k < out.size(); ++k) out.data()[k] = static_cast<float>(rng.normal());
}

class Sac final : public OffPolicy {
public:
  Sac(const SacConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
      const std::string& where, const std::optional<HerConfig>& her)
      : OffPolicy(config, network, seed, spec, "sac", where, her),
        cfg_(config),
        noise_rng_(Rng::derive(seed, rng_stream::training_noise)),
        log_alpha_(1, 1) {
    const nn::Activation act = nn::activation_from_string(network.activation, where + ": network.activation");
    Rng init = Rng::derive(seed, rng_stream::network_init);
    // The actor outputs the Gaussian's mean and log std for each action dimension.
    actor_ = nn::Mlp({observation_size_, network.hidden_sizes, 2 * action_dim_, act}, actor_gain, init, hidden_gain);
    const nn::MlpShape critic{observation_size_ + action_dim_, network.hidden_sizes, 1, act};
    for (nn::Mlp& q : q_) q = nn::Mlp(critic, critic_gain, init, hidden_gain);
    for (int i = 0; i < 2; ++i) q_target_[i] = q_[i];
    log_alpha_.value(0, 0) = static_cast<float>(std::log(cfg_.ent_coef));
    target_entropy_ = static_cast<float>(cfg_.target_entropy * action_dim_);

    nn::AdamConfig adam;
    adam.lr = static_cast<float>(cfg_.learning_rate);
    actor_optimizer_ = std::make_unique<nn::Adam>(actor_.params(), adam);
    nn::ParamList critic_params = q_[0].params();
    for (const nn::Param& p : q_[1].params()) critic_params.push_back(p);
    critic_optimizer_ = std::make_unique<nn::Adam>(critic_params, adam);
    alpha_optimizer_ = std::make_unique<nn::Adam>(nn::ParamList{nn::param_of(log_alpha_, "log_alpha")}, adam);
  }

  std::string name() const override { return "sac"; }

protected:
  void policy(const Eigen::MatrixXf& obs, bool deterministic, Rng& rng, Eigen::MatrixXf& actions) override;
  // The mode: tanh of the Gaussian's mean (the actor's first action_dim outputs), to the Box.
  PolicyProgram policy_program() const override {
    PolicyProgram program = policy_program_start();
    program.mlp(actor_);
    program.keep_rows(action_dim_);
    program.activate(nn::Activation::Tanh);
    add_env_action_ops(program);
    return program;
  }
  Metrics train(int steps, const TrainProgress& progress) override;
  nn::ParamList acting_params() override { return actor_.params(); }
  nn::ParamList other_params() override {
    nn::ParamList list;
    for (nn::Mlp* net : {&q_[0], &q_[1], &q_target_[0], &q_target_[1]})
      for (const nn::Param& p : net->params()) list.push_back(p);
    list.push_back(nn::param_of(log_alpha_, "log_alpha"));
    return list;
  }
  void save_training(std::ostream& out) const override;
  void load_training(std::istream& in, const std::string& source) override;

private:
  // Splits the actor's output into means and clamped log stds (and which ones were clamped).
  void split(const Eigen::MatrixXf& out, Eigen::MatrixXf& mean, Eigen::MatrixXf& log_std) const {
    mean = out.topRows(action_dim_);
    log_std = out.bottomRows(action_dim_).cwiseMax(sac::log_std_min).cwiseMin(sac::log_std_max);
  }
  void gradient_step(double* sums);

  SacConfig cfg_;
  Rng noise_rng_;
  nn::Mlp actor_;
  nn::Mlp q_[2], q_target_[2];
  nn::Tensor log_alpha_;
  float target_entropy_ = 0.0f;
  long long updates_ = 0;  // gradient steps taken (target-update clock)
  std::unique_ptr<nn::Adam> actor_optimizer_, critic_optimizer_, alpha_optimizer_;
  ReplayBatch batch_;
  // scratch
  Eigen::MatrixXf input_, next_input_, critic_in_, mean_, log_std_, noise_;
};

void Sac::policy(const Eigen::MatrixXf& obs, bool deterministic, Rng& rng, Eigen::MatrixXf& actions) {
  split(actor_.infer(actor_input(obs, input_)), mean_, log_std_);
  if (deterministic) {
    actions = nn::TanhGaussian::mode(mean_);
    return;
  }
  draw_normal(noise_, action_dim_, static_cast<int>(obs.cols()), rng);
  actions = nn::TanhGaussian(mean_, log_std_, noise_).actions();
}

// One SAC update on a minibatch, in Stable-Baselines3's order. sums: critic loss, actor loss,
// alpha, entropy estimate, mean Q.
void Sac::gradient_step(double* sums) {
  const int demos = sample_batch(batch_);
  const int b = cfg_.batch_size;
  const float inv_b = 1.0f / static_cast<float>(b);

  // 1. The current policy's reparameterised actions at s (the actor's training pass), and, for
  //    step 3, its actions at s': the same weights, so both passes run side by side (forward()
  //    and infer() keep their own buffers).
  Eigen::MatrixXf mean, log_std, noise, next_mean, next_log_std, next_noise;
  const Eigen::MatrixXf& obs_in = actor_input(batch_.observations, input_);
  const Eigen::MatrixXf& next_obs_in = actor_input(batch_.next_observations, next_input_);
  const Eigen::MatrixXf* outs[2] = {nullptr, nullptr};
  nn::run_side_by_side(2, [&](int i) { outs[i] = i == 0 ? &actor_.forward(obs_in) : &actor_.infer(next_obs_in); });
  const Eigen::MatrixXf& out = *outs[0];
  split(out, mean, log_std);
  draw_normal(noise, action_dim_, b, noise_rng_);
  const nn::TanhGaussian pi(mean, log_std, noise);

  // 2. Entropy coefficient: loss -log_alpha * mean(log pi + target_entropy); alpha of this step
  //    is the value before its update.
  const float alpha = std::exp(log_alpha_.value(0, 0));
  if (cfg_.auto_entropy) {
    log_alpha_.zero_grad();
    log_alpha_.grad(0, 0) = -(pi.log_probs().array() + target_entropy_).mean();
    average_gradients(alpha_optimizer_->params());
    alpha_optimizer_->step();
  }

  // 3. Soft TD targets from the target critics at s', with a' drawn from the current policy.
  split(*outs[1], next_mean, next_log_std);
  draw_normal(next_noise, action_dim_, b, noise_rng_);
  const nn::TanhGaussian next_pi(next_mean, next_log_std, next_noise);
  const Eigen::MatrixXf& next_in = critic_input(batch_.next_observations, next_pi.actions(), critic_in_);
  // The two critics' passes are independent: side by side on the learner's threads (nn/gemm.hpp),
  // each writing only its own network and outputs, so the bits do not depend on the thread count.
  Eigen::RowVectorXf target_q[2];
  nn::run_side_by_side(2, [&](int i) { target_q[i] = q_target_[i].infer(next_in).row(0); });
  const Eigen::VectorXf next_q = target_q[0].transpose().cwiseMin(target_q[1].transpose());
  const Eigen::VectorXf y = sac::soft_td_targets(batch_.rewards, batch_.terminated, next_q, next_pi.log_probs(), alpha,
                                                 static_cast<float>(cfg_.gamma));

  // 4. Critics: loss 0.5 sum_i mean((Q_i(s, a) - y)^2).
  const Eigen::MatrixXf& in = critic_input(batch_.observations, batch_.action_values, critic_in_);
  Eigen::RowVectorXf values[2];
  double losses[2];
  nn::run_side_by_side(2, [&](int i) {
    q_[i].zero_grad();
    values[i] = q_[i].forward(in).row(0);
    const Eigen::RowVectorXf d = values[i] - y.transpose();
    losses[i] = 0.5 * d.cast<double>().squaredNorm() / b;
    q_[i].backward(d * inv_b, false);
  });
  double critic_loss = 0.0, q_mean = 0.0;
  Eigen::RowVectorXf q_stored = Eigen::RowVectorXf::Constant(b, std::numeric_limits<float>::infinity());
  for (int i = 0; i < 2; ++i) {  // summed in critic order, as on one thread
    q_stored = q_stored.cwiseMin(values[i]);
    critic_loss += losses[i];
    q_mean += values[i].cast<double>().mean() / 2.0;
  }
  average_gradients(critic_optimizer_->params());
  critic_optimizer_->step();

  // 5. Actor: loss mean(alpha log pi(a|s) - min_i Q_i(s, a)), a = the actions of step 1, through
  //    the updated critics; dQ/da comes from the critic that gives the minimum.
  const Eigen::MatrixXf& pi_in = critic_input(batch_.observations, pi.actions(), critic_in_);
  Eigen::RowVectorXf q_pi[2];
  nn::run_side_by_side(2, [&](int i) { q_pi[i] = q_[i].forward(pi_in).row(0); });
  const Eigen::RowVectorXf& q0 = q_pi[0];
  const Eigen::RowVectorXf& q1 = q_pi[1];
  Eigen::MatrixXf d_q[2] = {Eigen::MatrixXf::Zero(1, b), Eigen::MatrixXf::Zero(1, b)};
  for (int j = 0; j < b; ++j) (q0[j] <= q1[j] ? d_q[0](0, j) : d_q[1](0, j)) = -inv_b;
  Eigen::MatrixXf d_in_each[2];  // through the critics, which this loss does not train
  nn::run_side_by_side(2, [&](int i) { d_in_each[i] = q_[i].input_gradient(d_q[i]); });
  const Eigen::MatrixXf d_in = d_in_each[0] + d_in_each[1];
  const Eigen::VectorXf d_log_prob = Eigen::VectorXf::Constant(b, alpha * inv_b);
  const nn::TanhGaussian::Grad g = pi.backward(d_in.bottomRows(action_dim_), d_log_prob);
  Eigen::MatrixXf d_out(2 * action_dim_, b);
  d_out.topRows(action_dim_) = g.mean;
  // Demonstrated columns: the Q-filtered cloning term pulls the policy's mean action tanh(mean)
  // towards them (the mode, not the draw: cloning the draws would fight the entropy term).
  double bc_loss = 0.0;
  if (demos > 0) {
    const Eigen::MatrixXf mode = nn::TanhGaussian::mode(mean);
    Eigen::MatrixXf d_mode = Eigen::MatrixXf::Zero(action_dim_, b);
    bc_loss = clone_demonstrations(demos, mode, batch_.action_values, q_stored, q0.cwiseMin(q1), d_mode);
    d_out.topRows(action_dim_).array() += d_mode.array() * (1.0f - mode.array().square());
  }
  // Clamped log stds pass no gradient.
  const Eigen::MatrixXf raw_log_std = out.bottomRows(action_dim_);
  d_out.bottomRows(action_dim_) =
      ((raw_log_std.array() >= sac::log_std_min) && (raw_log_std.array() <= sac::log_std_max)).select(g.log_std, 0.0f);
  actor_.zero_grad();
  actor_.backward(d_out, false);
  average_gradients(actor_optimizer_->params());
  actor_optimizer_->step();
  const double actor_loss =
      (alpha * pi.log_probs().array() - q0.transpose().array().min(q1.transpose().array())).cast<double>().mean();

  // 6. Target critics follow the critics.
  ++updates_;
  if (updates_ % cfg_.target_update_interval == 0)
    for (int i = 0; i < 2; ++i) q_target_[i].blend_values_from(q_[i], static_cast<float>(cfg_.tau));

  sums[0] += critic_loss;
  sums[1] += actor_loss;
  sums[2] += alpha;
  sums[3] += -pi.log_probs().cast<double>().mean();
  sums[4] += q_mean;
  sums[5] += bc_loss;
}

Metrics Sac::train(int steps, const TrainProgress& /*progress*/) {
  double sums[6] = {0, 0, 0, 0, 0, 0};
  for (int k = 0; k < steps; ++k) gradient_step(sums);
  const double m = std::max(steps, 1);
  Metrics metrics{{"critic_loss", sums[0] / m}, {"actor_loss", sums[1] / m},   {"ent_coef", steps ? sums[2] / m : std::exp(log_alpha_.value(0, 0))},
                  {"entropy", sums[3] / m},     {"q_mean", sums[4] / m}};
  if (has_demonstrations()) metrics.emplace_back("bc_loss", sums[5] / m);
  return metrics;
}

void Sac::save_training(std::ostream& out) const {
  auto& self = const_cast<Sac&>(*this);  // params() hands out mutable views; saving only reads them
  for (nn::Mlp* net : {&self.q_[0], &self.q_[1], &self.q_target_[0], &self.q_target_[1]}) nn::save_params(net->params(), out);
  nn::save_params({nn::param_of(self.log_alpha_, "log_alpha")}, out);
  actor_optimizer_->save_state(out);
  critic_optimizer_->save_state(out);
  alpha_optimizer_->save_state(out);
  write_string(out, rng_to_bytes(noise_rng_));
  write_u64(out, static_cast<std::uint64_t>(updates_));
}

void Sac::load_training(std::istream& in, const std::string& source) {
  for (nn::Mlp* net : {&q_[0], &q_[1], &q_target_[0], &q_target_[1]}) nn::load_params(net->params(), in, source);
  nn::load_params({nn::param_of(log_alpha_, "log_alpha")}, in, source);
  actor_optimizer_->load_state(in, source);
  critic_optimizer_->load_state(in, source);
  alpha_optimizer_->load_state(in, source);
  noise_rng_ = rng_from_bytes(read_string(in, source), source);
  const std::uint64_t updates = read_u64(in, source);
  if (updates > (1ull << 50)) throw Error(source + ": checkpoint holds an update count out of range (damaged file?)");
  updates_ = static_cast<long long>(updates);
}

}  // namespace

std::unique_ptr<Algorithm> make_sac(const SacConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where, const std::optional<HerConfig>& her) {
  return std::make_unique<Sac>(config, network, seed, spec, where, her);
}

// A squashed-Gaussian actor (mean and log std per action), two critics and their targets.
void estimate_memory(const SacConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  memory::actor_critics(c.network, spec, num_envs, p.buffer_size, p.batch_size, 2.0 * spec.action.dim(), false, "sac", e);
}

}  // namespace rdsim
