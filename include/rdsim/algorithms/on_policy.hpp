#pragma once
#include <memory>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/rollout.hpp"
#include "rdsim/nn/nn.hpp"

// What PPO and A2C share: an ActorCritic, an optimiser, a rollout of n_steps per env with GAE,
// acting, and the model/checkpoint state. Each algorithm adds only its train() step.
namespace rdsim {

class OnPolicy : public Algorithm {
public:
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;

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

  Spec spec_;
  RolloutSettings settings_;
  std::unique_ptr<ActorCritic> policy_;
  std::unique_ptr<nn::Optimizer> optimizer_;  // use_optimizer() in the derived constructor
  Rng sample_rng_;
  Rng shuffle_rng_;
  RolloutBuffer rollout_;
  long long updates_ = 0;
  std::vector<float> gradient_buffer_;
};

}  // namespace rdsim
