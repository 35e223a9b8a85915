#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/observation_normalizer.hpp"
#include "rdsim/policy/policy_program.hpp"
#include "rdsim/algorithms/demonstration_replay.hpp"
#include "rdsim/algorithms/demonstrations.hpp"
#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/hindsight_replay.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/off_policy_config.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/nn/param.hpp"

// What the continuous-action off-policy methods (SAC, TD3/DDPG) share: a replay buffer of Box
// transitions, the collect-then-train schedule (train_freq VecEnv steps, then gradient_steps
// minibatch updates once more than learning_starts env steps were taken), uniform random actions
// before learning starts, the rescaling between the env's Box and the networks' [-1, 1], and the
// model/checkpoint layout, and hindsight experience replay on goal envs (a "her" config,
// hindsight_replay.hpp), and demonstrations (demonstration_replay.hpp: a share of every minibatch,
// a Q-filtered cloning term in the actor's loss, pre-training). Each method adds its networks, its
// exploration and its train step.
namespace rdsim {

class OffPolicy : public Algorithm {
public:
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  void enable_observation_normalization() override;
  // Model: the acting weights. Checkpoint: those, then the method's training state, the random
  // streams, the counters and the replay buffer.
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;
  // Every gradient step averages the gradients of each optimiser over the ranks before it steps
  // (average_gradients below). The critics, targets and entropy coefficient are outside the model,
  // so the ranks share them too.
  bool data_parallel() const override { return true; }
  void save_all_weights(std::ostream& out) const override;
  void load_all_weights(std::istream& in, const std::string& source) override;
  // The demonstrations' own buffer (rebuilt from the file on resume, so not in checkpoints), then
  // with `pretrain` bc_epochs passes of gradient steps on them alone.
  std::vector<Metrics> learn_from_demonstrations(const DemoFile& demos, const DemonstrationsConfig& config, Rng& rng,
                                                 bool pretrain) override;

  // The Box action for network actions in [-1, 1]: low + (a + 1) (high - low) / 2, clipped.
  Action env_action(const Eigen::Ref<const Eigen::VectorXf>& normalized) const;

protected:
  // `algorithm` and `where` name the method and the config file in messages: the env must have
  // vector observations and a bounded Box action space. network.input_scale is kept for
  // actor_input() and critic_input(). `her`: relabel goals in hindsight (the env must be
  // goal-conditioned, core/goal_layout.hpp).
  OffPolicy(const OffPolicyConfig& settings, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
            const std::string& algorithm, const std::string& where, const std::optional<HerConfig>& her);

  // A minibatch of settings_.batch_size transitions for a gradient step: uniform from the replay
  // buffer, or with hindsight goals when HER is on; with demonstrations its first
  // demonstrations.demo_fraction of columns are demonstrated (all of them while pre-training or
  // while the replay buffer is empty). Returns how many columns are demonstrated.
  int sample_batch(ReplayBatch& out);
  // Q-filtered behaviour cloning (Nair et al. 2018) on the first `demos` columns of a minibatch:
  // where the critic values the demonstrated action (q_demo) above the policy's (q_policy) (every
  // column while pre-training), adds
  // the gradient of bc_weight x mean over those columns of |policy_actions - demo_actions|^2 to
  // d_actions (the actor loss's gradient w.r.t. its actions). Returns that loss (0 without demos).
  double clone_demonstrations(int demos, const Eigen::MatrixXf& policy_actions, const Eigen::MatrixXf& demo_actions,
                              const Eigen::RowVectorXf& q_demo, const Eigen::RowVectorXf& q_policy,
                              Eigen::Ref<Eigen::MatrixXf> d_actions) const;
  bool has_demonstrations() const { return demos_ != nullptr; }

  // The networks' inputs: observations times network.input_scale (actor), and those stacked
  // over the actions (critics: Q(s, a) sees [scale * s; a]).
  const Eigen::MatrixXf& actor_input(const Eigen::MatrixXf& observations, Eigen::MatrixXf& scratch) const;
  // A policy program (policy_program.hpp) with actor_input()'s operations; the actor's follow, then
  // add_env_action_ops() (env_action: [-1, 1] to the Box).
  PolicyProgram policy_program_start() const;
  void add_env_action_ops(PolicyProgram& program) const;
  const Eigen::MatrixXf& critic_input(const Eigen::MatrixXf& observations, const Eigen::MatrixXf& actions,
                                      Eigen::MatrixXf& scratch) const;

  // Actions in [-1, 1] (action_dim x n) for encoded observations (one column each): the policy's
  // mean action when `deterministic`, else an exploring one drawn with `rng`.
  virtual void policy(const Eigen::MatrixXf& observations, bool deterministic, Rng& rng, Eigen::MatrixXf& actions) = 0;
  // Env `env` finished an episode (stateful exploration noise restarts).
  virtual void on_episode_end(int /*env*/) {}
  // `steps` gradient steps (0 before learning starts) on minibatches from buffer_; the metrics
  // have the same names and order whatever `steps` is.
  virtual Metrics train(int steps, const TrainProgress& progress) = 0;
  // The weights acting needs (model.bin), and everything else an exact resume needs.
  virtual nn::ParamList acting_params() = 0;
  // The trained weights outside acting_params() (critics, target networks, entropy coefficient).
  virtual nn::ParamList other_params() = 0;
  virtual void save_training(std::ostream& out) const = 0;
  virtual void load_training(std::istream& in, const std::string& source) = 0;

  // Data-parallel training: the gradients of `params` become their mean over the ranks (nothing
  // happens in one process). Just before the optimiser's step.
  void average_gradients(const nn::ParamList& params);

  Spec spec_;
  int observation_size_;
  int action_dim_;
  float input_scale_;
  ObservationNormalizer normalizer_;  // "normalize_observations" (off by default)
  OffPolicyConfig settings_;
  ReplayBuffer buffer_;
  std::optional<HindsightReplay> her_;  // with a "her" config
  std::optional<HerConfig> her_config_;
  std::unique_ptr<DemonstrationReplay> demos_;  // with a "demonstrations" config
  DemonstrationsConfig demo_cfg_;
  bool demos_only_ = false;  // pre-training
  Rng explore_rng_;  // warm-up actions and exploration noise
  Rng replay_rng_;   // minibatch draws
  long long gradient_steps_ = 0;

private:
  void collect_step(VecEnv& envs, bool warmup);
  void observe_demonstrations(const DemoFile& demos);

  // scratch, reused so the collection loop does not allocate
  Eigen::MatrixXf obs_, actions_;
  std::vector<Action> env_actions_;
  std::vector<Observation> prev_obs_;
  Observation next_obs_;
  std::vector<float> gradient_buffer_;
};

}  // namespace rdsim
