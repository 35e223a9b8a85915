// Behaviour cloning: supervised learning of the demonstrated actions (behavior_cloning.hpp), then
// the cloned policy is only run.
#include "rdsim/algorithms/bc.hpp"

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/behavior_cloning.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/nn/nn.hpp"
#include "memory_footprint.hpp"

namespace rdsim {
namespace {

class Bc final : public Algorithm {
public:
  Bc(const BcConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec)
      : cfg_(config), spec_(spec), act_rng_(Rng::derive(seed, rng_stream::action_sampling)) {
    Rng init = Rng::derive(seed, rng_stream::network_init);
    policy_ = std::make_unique<ActorCritic>(spec, network, init);
  }

  std::string name() const override { return "bc"; }
  // Nothing changes the weights after fitting, which every rank does alike (the run's
  // demonstrations stream, not the rank's) before rank 0's weights are shared.
  bool data_parallel() const override { return true; }
  long long step_multiple(int num_envs) const override { return static_cast<long long>(cfg_.n_steps) * num_envs; }

  std::vector<Metrics> learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config, Rng& rng,
                                                 bool pretrain) override {
    if (!pretrain) return {};  // a resumed run: the checkpoint holds the cloned weights
    // The returns' discount does not matter: bc fits no critic.
    const DemoSplit data = split_demonstrations(demos, spec_.observation, config.validation_fraction, 0.99, rng);
    std::vector<Metrics> rows = fit_to_demonstrations(*policy_, data, config, false, rng);
    fitted_ = true;
    if (!rows.empty()) {
      const Metrics& last = rows.back();  // epoch, actor_loss, actor_val_loss, actor_val_error
      summary_ = {{"fit_epochs", last[0].second},
                  {"fit_actor_loss", last[1].second},
                  {"fit_actor_val_loss", last[2].second},
                  {"fit_actor_val_error", last[3].second}};
    }
    return rows;
  }

  Metrics update(VecEnv& envs, const TrainProgress&) override {
    if (!fitted_) throw Error("bc: the policy has not learnt from demonstrations (the config needs a \"demonstrations\" object)");
    const int n = envs.size();
    obs_.resize(policy_->observation_size(), n);
    actions_.resize(static_cast<std::size_t>(n));
    for (int t = 0; t < cfg_.n_steps; ++t) {
      for (int i = 0; i < n; ++i) encode_observation(envs.observations(), i, obs_.col(i));
      policy_->act(obs_, cfg_.deterministic, act_rng_, act_);
      for (int i = 0; i < n; ++i) actions_[static_cast<std::size_t>(i)] = policy_->env_action(act_.actions.col(i));
      envs.step(actions_);
    }
    return summary_;
  }

  PolicyProgram policy_program() const override { return policy_->policy_program(name(), spec_.observation); }

  Action act(const Observation& observation, bool deterministic, Rng& rng) override {
    Eigen::MatrixXf obs(policy_->observation_size(), 1);
    encode_observation(observation, spec_.observation, obs.col(0));
    ActBatch out;
    policy_->act(obs, deterministic, rng, out);
    return policy_->env_action(out.actions.col(0));
  }

  void save(std::ostream& out, bool training_state) const override {
    nn::save_params(policy_->params(), out);
    if (!training_state) return;
    write_string(out, rng_to_bytes(act_rng_));
    write_u32(out, static_cast<std::uint32_t>(summary_.size()));
    for (const auto& [name, value] : summary_) {
      write_string(out, name);
      write_f64(out, value);
    }
  }

  void load(std::istream& in, bool training_state, const std::string& source) override {
    nn::load_params(policy_->params(), in, source);
    fitted_ = true;  // a model or checkpoint holds a fitted policy
    if (!training_state) return;
    act_rng_ = rng_from_bytes(read_string(in, source), source);
    const std::uint32_t n = read_u32(in, source);
    if (n > 16) throw Error(source + ": file is damaged (bc summary)");
    summary_.clear();
    for (std::uint32_t k = 0; k < n; ++k) {
      std::string name = read_string(in, source);
      summary_.push_back({std::move(name), read_f64(in, source)});
    }
  }

private:
  BcConfig cfg_;
  Spec spec_;
  std::unique_ptr<ActorCritic> policy_;
  Rng act_rng_;
  bool fitted_ = false;
  // What the fit ended with: the algorithm's progress.csv columns.
  Metrics summary_ = {{"fit_epochs", 0.0}, {"fit_actor_loss", 0.0}, {"fit_actor_val_loss", 0.0}, {"fit_actor_val_error", 0.0}};
  Eigen::MatrixXf obs_;
  ActBatch act_;
  std::vector<Action> actions_;
};

}  // namespace

std::unique_ptr<Algorithm> make_bc(const BcConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                   const Spec& spec, const std::string& /*where*/) {
  return std::make_unique<Bc>(config, network, seed, spec);
}

// An actor-critic run n_steps x num_envs per update; its training passes (on the demonstrations,
// batch_size samples) happen before. The demonstrations themselves are bounded by the demo file's
// reader, not estimated here.
void estimate_memory(const BcConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  const double rollout = static_cast<double>(p.n_steps) * num_envs;
  const double batch = c.demonstrations ? std::max<double>(c.demonstrations->batch_size, rollout) : rollout;
  memory::on_policy(c.network, spec, num_envs, p.n_steps, batch, "bc", c.source, e);
}

}  // namespace rdsim
