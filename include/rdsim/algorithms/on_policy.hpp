#pragma once
#include <memory>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/behavior_cloning.hpp"
#include "rdsim/algorithms/rollout.hpp"
#include "rdsim/nn/nn.hpp"

// What PPO and A2C share: an ActorCritic, an optimiser, a rollout of n_steps per env with GAE,
// acting, and the model/checkpoint state. Each algorithm adds only its train() step.
namespace rdsim {

class OnPolicy : public Algorithm {
public:
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  void enable_observation_normalization() override;
  PolicyProgram policy_program() const override;
  // PPO and A2C average every minibatch's gradients over the ranks (average_gradients below).
  bool data_parallel() const override { return true; }
  long long step_multiple(int num_envs) const override { return static_cast<long long>(settings_.n_steps) * num_envs; }
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;
  // Pre-trains the actor (and with fit_critic the critic) on the demonstrations (behavior_cloning.hpp).
  std::vector<Metrics> learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config, Rng& rng,
                                                 bool pretrain) override;

  ActorCritic& policy() { return *policy_; }

protected:
  struct RolloutSettings {
    int n_steps;
    double gamma;
    double gae_lambda;
  };
  OnPolicy(const NetworkConfig& network, std::uint64_t seed, const Spec& spec, RolloutSettings settings);

  // Creates optimizer_ over the policy's parameters (the derived constructor picks the rule).
  void use_optimizer(const nn::AdamConfig& adam);
  void use_optimizer(const nn::RmsPropConfig& rms);

  // Learns from the filled rollout_ (advantages and returns computed). `remaining` goes from 1
  // at the start of training to 0 at the end (schedules).
  virtual Metrics train(double remaining) = 0;

  // Data-parallel training: the gradients of `params` become their mean over the ranks (nothing
  // happens in one process). Between backward() and gradient clipping.
  void average_gradients(const nn::ParamList& params);

  // demonstrations.bc_weight (demonstrations.hpp): whether the cloning term is on, and its weight
  // in this update.
  bool demonstration_term() const { return demo_weight_ > 0.0 && demo_steps_.size() > 0; }
  double demonstration_weight() const;
  // Accumulates (after the RL loss's backward, before clipping) the gradient of
  // demonstration_weight() x mean -log pi(a | s) over `batch` demonstrated steps drawn with
  // shuffle_rng_; returns that mean (0 when the term is off).
  double add_demonstration_gradient(int batch);

  Spec spec_;
  RolloutSettings settings_;
  std::unique_ptr<ActorCritic> policy_;
  std::unique_ptr<nn::Optimizer> optimizer_;  // use_optimizer() in the derived constructor
  Rng sample_rng_;
  Rng shuffle_rng_;
  RolloutBuffer rollout_;
  long long updates_ = 0;
  std::vector<float> gradient_buffer_;

private:
  DemoTransitions demo_steps_;  // the demonstrations' training episodes (bc_weight > 0)
  double demo_weight_ = 0.0, demo_decay_ = 1.0;
};

}  // namespace rdsim
