#include "rdsim/algorithms/on_policy.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rdsim/algorithms/advantage.hpp"
#include "rdsim/algorithms/behavior_cloning.hpp"
#include "rdsim/algorithms/gradient_averaging.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"

namespace rdsim {

OnPolicy::OnPolicy(const NetworkConfig& network, std::uint64_t seed, const Spec& spec, RolloutSettings settings)
    : spec_(spec),
      settings_(settings),
      sample_rng_(Rng::derive(seed, rng_stream::action_sampling)),
      shuffle_rng_(Rng::derive(seed, rng_stream::minibatch_shuffle)) {
  Rng init = Rng::derive(seed, rng_stream::network_init);
  policy_ = std::make_unique<ActorCritic>(spec, network, init);
}

void OnPolicy::use_optimizer(const nn::AdamConfig& adam) {
  optimizer_ = std::make_unique<nn::Adam>(policy_->params(), adam);
}

void OnPolicy::use_optimizer(const nn::RmsPropConfig& rms) {
  optimizer_ = std::make_unique<nn::RmsProp>(policy_->params(), rms);
}

Metrics OnPolicy::update(VecEnv& envs, const TrainProgress& progress) {
  if (rollout_.envs != envs.size() || rollout_.steps != settings_.n_steps) {
    rollout_.resize(settings_.n_steps, envs.size(), policy_->observation_size(), policy_->action_dim());
  }
  ObservationNormalizer& normalizer = policy_->normalizer();
  if (normalizer.enabled() && updates_ == 0) {
    // The first rollout already sees standardised inputs: those of the envs' first observations.
    Eigen::MatrixXf scratch;
    normalizer.observe(network_input(envs.observations(), scratch));
    normalizer.refresh(communicator());
  }
  collect_rollout(envs, *policy_, sample_rng_, rollout_);
  compute_gae(rollout_, static_cast<float>(settings_.gamma), static_cast<float>(settings_.gae_lambda));
  ++updates_;
  Metrics m = train(progress.remaining(envs.timesteps()));
  if (normalizer.enabled()) {  // the next rollout's inputs: the statistics with this one's observations
    normalizer.observe(rollout_.observations);
    normalizer.refresh(communicator());
  }
  return m;
}

PolicyProgram OnPolicy::policy_program() const { return policy_->policy_program(name(), spec_.observation); }

void OnPolicy::enable_observation_normalization() {
  policy_->normalizer() = ObservationNormalizer(policy_->observation_size());
}

void OnPolicy::average_gradients(const nn::ParamList& params) {
  rdsim::average_gradients(communicator(), params, gradient_buffer_);
}

Action OnPolicy::act(const Observation& observation, bool deterministic, Rng& rng) {
  Eigen::MatrixXf obs(policy_->observation_size(), 1);
  encode_observation(observation, spec_.observation, obs.col(0));
  ActBatch out;
  policy_->act(obs, deterministic, rng, out);
  return policy_->env_action(out.actions.col(0));
}

void OnPolicy::save(std::ostream& out, bool training_state) const {
  nn::save_params(policy_->params(), out);
  policy_->normalizer().save(out, training_state);
  if (!training_state) return;
  optimizer_->save_state(out);
  write_string(out, rng_to_bytes(sample_rng_));
  write_string(out, rng_to_bytes(shuffle_rng_));
  write_u64(out, static_cast<std::uint64_t>(updates_));
}

void OnPolicy::load(std::istream& in, bool training_state, const std::string& source) {
  nn::load_params(policy_->params(), in, source);
  policy_->normalizer().load(in, training_state, source);
  if (!training_state) return;
  optimizer_->load_state(in, source);
  sample_rng_ = rng_from_bytes(read_string(in, source), source);
  shuffle_rng_ = rng_from_bytes(read_string(in, source), source);
  const std::uint64_t updates = read_u64(in, source);
  if (updates > (1ull << 50)) throw Error(source + ": checkpoint holds an update count out of range (damaged file?)");
  updates_ = static_cast<long long>(updates);
}

std::vector<Metrics> OnPolicy::learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config,
                                                         Rng& rng, bool pretrain) {
  DemoSplit data = split_demonstrations(demos, spec_.observation, config.validation_fraction, settings_.gamma, rng);
  demo_weight_ = config.bc_weight;
  demo_decay_ = config.bc_weight_decay;
  std::vector<Metrics> rows;
  // A resumed run keeps only the demonstrations for the cloning term: its checkpoint holds the
  // pre-trained weights.
  if (pretrain) rows = fit_to_demonstrations(*policy_, data, config, config.fit_critic, rng);
  if (demo_weight_ > 0.0) demo_steps_ = std::move(data.train);
  return rows;
}

double OnPolicy::demonstration_weight() const {
  return demo_weight_ * std::pow(demo_decay_, static_cast<double>(std::max<long long>(updates_ - 1, 0)));
}

double OnPolicy::add_demonstration_gradient(int batch) {
  if (!demonstration_term()) return 0.0;
  const float w = static_cast<float>(demonstration_weight());
  Eigen::MatrixXf obs(demo_steps_.observations.rows(), batch), actions(demo_steps_.actions.rows(), batch);
  for (int j = 0; j < batch; ++j) {
    const auto i = static_cast<Eigen::Index>(shuffle_rng_.below(static_cast<std::uint64_t>(demo_steps_.size())));
    obs.col(j) = demo_steps_.observations.col(i);
    actions.col(j) = demo_steps_.actions.col(i);
  }
  const PolicyEval& ev = policy_->evaluate(obs, actions);
  policy_->backward(Eigen::VectorXf::Constant(batch, -w / static_cast<float>(batch)), Eigen::VectorXf(),
                    Eigen::VectorXf::Zero(batch));
  return -ev.log_probs.cast<double>().mean();
}

}  // namespace rdsim
