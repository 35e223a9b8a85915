#include "rdsim/algorithms/off_policy.hpp"

#include <algorithm>
#include <cmath>

#include "rdsim/algorithms/transition_step.hpp"
#include "rdsim/algorithms/gradient_averaging.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/nn/serialize.hpp"

namespace rdsim {
namespace {

// Observations x buffer_size are stored twice (observation and next observation), plus the actions.
constexpr double kMaxReplayBytes = 16.0 * 1024 * 1024 * 1024;

const Spec& checked_spec(const Spec& spec, const OffPolicyConfig& settings, const std::string& algorithm,
                         const std::string& where, bool her) {
  if (her) require_goal_env(spec, where);
  if (spec.action.discrete)
    throw Error(where + ": algorithm: \"" + algorithm + "\" needs a continuous (Box) action space, env \"" +
                spec.env_name + "\" has discrete actions (set env.is_discrete to false, or use dqn/ppo/a2c)");
  if (spec.observation.type != ObsType::Float32)
    throw Error(where + ": algorithm: \"" + algorithm + "\" needs vector observations, env \"" + spec.env_name +
                "\" gives pixels (use env.observation \"ground_truth\")");
  const int dim = spec.action.dim();
  if (dim <= 0 || spec.action.high.size() != dim || !spec.action.low.allFinite() || !spec.action.high.allFinite() ||
      !(spec.action.high.array() > spec.action.low.array()).all())
    throw Error(where + ": algorithm: \"" + algorithm + "\" needs finite action bounds, env \"" + spec.env_name +
                "\" has none");
  // HER adds an episode start (8 bytes) and length (4 bytes) per transition.
  const double bytes = static_cast<double>(settings.buffer_size) *
                       (4.0 * (2.0 * spec.observation.size() + static_cast<double>(dim) + 2.0) + (her ? 12.0 : 0.0));
  if (bytes > kMaxReplayBytes)
    throw Error(where + ": " + algorithm + ".buffer_size: " + std::to_string(settings.buffer_size) +
                " transitions need " + std::to_string(static_cast<long long>(bytes / (1 << 20))) +
                " MiB, more than the 16 GiB allowed; use a smaller buffer");
  return spec;
}

}  // namespace

OffPolicy::OffPolicy(const OffPolicyConfig& settings, const NetworkConfig& network, std::uint64_t seed,
                     const Spec& spec, const std::string& algorithm, const std::string& where,
                     const std::optional<HerConfig>& her)
    : spec_(checked_spec(spec, settings, algorithm, where, her.has_value())),
      observation_size_(observation_input_size(spec.observation)),
      action_dim_(spec.action.dim()),
      input_scale_(static_cast<float>(network.input_scale)),
      settings_(settings),
      buffer_(settings.buffer_size, spec.observation, spec.action.dim()),
      explore_rng_(Rng::derive(seed, rng_stream::exploration)),
      replay_rng_(Rng::derive(seed, rng_stream::replay_sampling)) {
  if (her) her_.emplace(*her, spec_.goal, settings.buffer_size);
  her_config_ = her;
}

int OffPolicy::sample_batch(ReplayBatch& out) {
  const int b = settings_.batch_size;
  buffer_.shape_batch(b, out);
  int demos = 0;
  if (demos_)
    demos = demos_only_ || buffer_.size() == 0 ? b : static_cast<int>(std::lround(demo_cfg_.demo_fraction * b));
  if (demos > 0) demos_->sample_into(0, demos, replay_rng_, out);
  if (demos == b) return demos;
  if (her_)
    her_->sample_into(buffer_, demos, b - demos, replay_rng_, out);
  else
    buffer_.sample_into(demos, b - demos, replay_rng_, out);
  return demos;
}

double OffPolicy::clone_demonstrations(int demos, const Eigen::MatrixXf& policy_actions,
                                       const Eigen::MatrixXf& demo_actions, const Eigen::RowVectorXf& q_demo,
                                       const Eigen::RowVectorXf& q_policy, Eigen::Ref<Eigen::MatrixXf> d_actions) const {
  if (demos == 0 || demo_cfg_.bc_weight <= 0.0) return 0.0;
  const auto weight = static_cast<float>(demo_cfg_.bc_weight) / static_cast<float>(demos);
  double loss = 0.0;
  for (int j = 0; j < demos; ++j) {
    // The Q-filter: clone only what the critic rates higher. Not while pre-training: a critic that has
    // seen only the demonstrated actions rates the others arbitrarily.
    if (!demos_only_ && !(q_demo[j] > q_policy[j])) continue;
    const Eigen::VectorXf diff = policy_actions.col(j) - demo_actions.col(j);
    loss += weight * diff.squaredNorm();
    d_actions.col(j) += 2.0f * weight * diff;
  }
  return loss;
}

std::vector<Metrics> OffPolicy::learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config,
                                                          Rng& /*rng*/, bool pretrain) {
  demo_cfg_ = config;
  const Eigen::ArrayXf low = spec_.action.low.array(), high = spec_.action.high.array();
  demos_ = std::make_unique<DemonstrationReplay>(demos, spec_, her_config_, [&](const Action& a) -> Eigen::VectorXf {
    // The inverse of env_action: the env's Box to the networks' [-1, 1].
    return (2.0f * (a.values.array() - low) / (high - low) - 1.0f).cwiseMax(-1.0f).cwiseMin(1.0f).matrix();
  }, config.shift, config.scatter, config.scatter_goal);
  std::vector<Metrics> rows;
  // A resumed run's checkpoint holds the statistics, the demonstrations' included.
  if (!pretrain) return rows;
  if (normalizer_.enabled()) observe_demonstrations(demos);
  // Gradient steps on the demonstrations alone (DQfD's and Nair et al.'s first phase).
  const long long per_epoch =
      std::max<long long>(1, (demos_->transitions() + settings_.batch_size - 1) / settings_.batch_size);
  demos_only_ = true;
  for (int epoch = 1; epoch <= config.bc_epochs; ++epoch) {
    Metrics row{{"epoch", epoch}};
    const Metrics m = train(static_cast<int>(per_epoch), {0, 1});
    row.insert(row.end(), m.begin(), m.end());
    rows.push_back(std::move(row));
  }
  demos_only_ = false;
  return rows;
}

void OffPolicy::observe_demonstrations(const DemoFile& demos) {
  // normalize_observations: the statistics start from every demonstrated observation, so the
  // pre-training sees standardised inputs; the env's observations join them from the first update.
  for (const DemoEpisode& e : demos.episodes) {
    Eigen::MatrixXf obs(observation_size_, static_cast<Eigen::Index>(e.observations.size()));
    for (std::size_t t = 0; t < e.observations.size(); ++t)
      encode_observation(e.observations[t], spec_.observation, obs.col(static_cast<Eigen::Index>(t)));
    normalizer_.observe(obs);
  }
  normalizer_.refresh(communicator());
}

const Eigen::MatrixXf& OffPolicy::actor_input(const Eigen::MatrixXf& observations, Eigen::MatrixXf& scratch) const {
  return normalizer_.network_input(observations, input_scale_, scratch);
}

const Eigen::MatrixXf& OffPolicy::critic_input(const Eigen::MatrixXf& observations, const Eigen::MatrixXf& actions,
                                               Eigen::MatrixXf& scratch) const {
  scratch.resize(observations.rows() + actions.rows(), observations.cols());
  if (normalizer_.enabled())
    normalizer_.apply(observations, scratch.topRows(observations.rows()));
  else
    scratch.topRows(observations.rows()) = observations * input_scale_;
  scratch.bottomRows(actions.rows()) = actions;
  return scratch;
}

PolicyProgram OffPolicy::policy_program_start() const {
  PolicyProgram program;
  program.algorithm = name();
  program.input_size = observation_size_;
  program.action_size = action_dim_;
  normalizer_.add_input_ops(program, input_scale_);
  return program;
}

void OffPolicy::add_env_action_ops(PolicyProgram& program) const { program.rescale(spec_.action.low, spec_.action.high); }

Action OffPolicy::env_action(const Eigen::Ref<const Eigen::VectorXf>& normalized) const {
  const Eigen::ArrayXf a = normalized.array().cwiseMax(-1.0f).cwiseMin(1.0f);
  const Eigen::ArrayXf low = spec_.action.low.array(), high = spec_.action.high.array();
  return Action::continuous((low + 0.5f * (a + 1.0f) * (high - low)).cwiseMin(high).matrix());
}

void OffPolicy::collect_step(VecEnv& envs, bool warmup) {
  const int n = envs.size();
  obs_.resize(observation_size_, n);
  for (int i = 0; i < n; ++i) encode_observation(envs.observations(), i, obs_.col(i));
  if (normalizer_.enabled()) normalizer_.observe(obs_);
  if (warmup) {
    // Before learning starts every action is uniform in the Box (the networks are untrained).
    actions_.resize(action_dim_, n);
    for (Eigen::Index k = 0; k < actions_.size(); ++k) actions_.data()[k] = static_cast<float>(explore_rng_.uniform(-1.0, 1.0));
  } else {
    policy(obs_, false, explore_rng_, actions_);
  }
  env_actions_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) env_actions_[static_cast<std::size_t>(i)] = env_action(actions_.col(i));
  step_transitions(envs, env_actions_, prev_obs_, next_obs_,
                   [&](int i, const Observation& obs, const EnvStep& s, const Observation& next) {
                     buffer_.add(obs, actions_.col(i), s.reward, next, s.terminated);
                     if (her_) her_->added(buffer_.last_slot(), i, n, s.done());
                     if (s.done()) on_episode_end(i);
                   });
}

Metrics OffPolicy::update(VecEnv& envs, const TrainProgress& progress) {
  const int n = envs.size();
  const long long calls = progress.phase_steps(settings_.train_freq, n);
  for (long long c = 0; c < calls; ++c) collect_step(envs, envs.timesteps() < settings_.learning_starts);
  const bool learning = envs.timesteps() > settings_.learning_starts;
  Metrics m = train(learning ? settings_.gradient_steps : 0, {envs.timesteps(), progress.total_timesteps});
  if (learning) gradient_steps_ += settings_.gradient_steps;
  m.emplace_back("gradient_steps", static_cast<double>(gradient_steps_));
  m.emplace_back("buffer_size", static_cast<double>(buffer_.size()));
  if (her_) m.emplace_back("her_relabelable", static_cast<double>(her_->relabelable()));
  // The next update's inputs: the statistics with this one's observations.
  if (normalizer_.enabled()) normalizer_.refresh(communicator());
  return m;
}

void OffPolicy::enable_observation_normalization() { normalizer_ = ObservationNormalizer(observation_size_); }

Action OffPolicy::act(const Observation& observation, bool deterministic, Rng& rng) {
  Eigen::MatrixXf obs(observation_size_, 1), action;
  encode_observation(observation, spec_.observation, obs.col(0));
  policy(obs, deterministic, rng, action);
  return env_action(action.col(0));
}

void OffPolicy::save(std::ostream& out, bool training_state) const {
  auto& self = const_cast<OffPolicy&>(*this);  // params() hands out mutable views; saving only reads them
  nn::save_params(self.acting_params(), out);
  normalizer_.save(out, training_state);
  if (!training_state) return;
  save_training(out);
  write_string(out, rng_to_bytes(explore_rng_));
  write_string(out, rng_to_bytes(replay_rng_));
  write_u64(out, static_cast<std::uint64_t>(gradient_steps_));
  buffer_.save(out);
  if (her_) her_->save(out, buffer_.size());
}

void OffPolicy::save_all_weights(std::ostream& out) const {
  auto& self = const_cast<OffPolicy&>(*this);  // params() hands out mutable views; saving only reads them
  nn::save_params(self.acting_params(), out);
  normalizer_.save(out, false);
  nn::save_params(self.other_params(), out);
}

void OffPolicy::load_all_weights(std::istream& in, const std::string& source) {
  nn::load_params(acting_params(), in, source);
  normalizer_.load(in, false, source);
  nn::load_params(other_params(), in, source);
}

void OffPolicy::average_gradients(const nn::ParamList& params) {
  rdsim::average_gradients(communicator(), params, gradient_buffer_);
}

void OffPolicy::load(std::istream& in, bool training_state, const std::string& source) {
  nn::load_params(acting_params(), in, source);
  normalizer_.load(in, training_state, source);
  if (!training_state) return;
  load_training(in, source);
  explore_rng_ = rng_from_bytes(read_string(in, source), source);
  replay_rng_ = rng_from_bytes(read_string(in, source), source);
  const std::uint64_t gradient_steps = read_u64(in, source);
  if (gradient_steps > (1ull << 50)) throw Error(source + ": checkpoint holds a gradient-step count out of range (damaged file?)");
  gradient_steps_ = static_cast<long long>(gradient_steps);
  buffer_.load(in, source);
  if (her_) her_->load(in, buffer_.size(), source);
}

}  // namespace rdsim
