#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>

#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/observation_normalizer.hpp"
#include "rdsim/policy/policy_program.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/nn/cnn.hpp"
#include "rdsim/nn/nn.hpp"

// Policy and value networks of the on-policy algorithms (PPO, A2C) over the nn:: API:
// separate actor and critic MLPs, or one shared trunk with two linear heads. Pixel (UInt8)
// observations always get a shared CNN trunk (network.cnn) with two linear heads. Discrete action
// spaces get a Categorical over logits, Box spaces a DiagGaussian with a state-independent,
// trainable log std. Observations come in encoded (see observation_batch.hpp); every pass first
// multiplies them by network.input_scale.
namespace rdsim {

// True when observations of this space are images that need a CNN ({height, width, channels}: UInt8
// colour, or the Float32 channels of EnvConfig::image_channels).
bool is_image_space(const ObservationSpace& space);

// The network described by `config` (network.cnn) for images of `space`, `outputs` outputs
// (its last fc layer when used as a feature trunk). rdsim::Error naming `where` (e.g.
// "cfg.json: network.cnn") when the space is not an image or the convs do not fit it.
nn::CnnShape cnn_shape(const CnnConfig& config, const ObservationSpace& space, int outputs, const std::string& where);

// Builds the Cnn of cnn_shape(), turning shape errors into messages naming `where`.
nn::Cnn make_cnn(const nn::CnnShape& shape, float output_gain, Rng& rng, const std::string& where);

// The result of acting on a batch (one column per observation).
struct ActBatch {
  Eigen::MatrixXf actions;    // action_dim x n: raw samples (discrete: the index as a float)
  Eigen::VectorXf log_probs;  // log pi(action | obs)
  Eigen::VectorXf values;     // V(obs)
};

// A training forward pass over a minibatch; backward() differentiates through it.
struct PolicyEval {
  Eigen::VectorXf log_probs;
  Eigen::VectorXf entropy;
  Eigen::VectorXf values;
};

class ActorCritic {
public:
  // Weights drawn from `init_rng` (orthogonal init: sqrt(2) hidden, 0.01 policy head, 1 value head).
  ActorCritic(const Spec& spec, const NetworkConfig& config, Rng& init_rng);
  ActorCritic(const ActorCritic&) = delete;  // optimisers hold pointers into the tensors
  ActorCritic& operator=(const ActorCritic&) = delete;

  // Inference (does not disturb the training caches).
  void act(const Eigen::MatrixXf& obs, bool deterministic, Rng& rng, ActBatch& out);
  Eigen::VectorXf predict_values(const Eigen::MatrixXf& obs);

  // Training: forward over (obs, actions) keeping what backward() needs. obs must stay alive and
  // unchanged until backward(): a CNN trunk keeps a reference to it, not a copy.
  const PolicyEval& evaluate(const Eigen::MatrixXf& obs, const Eigen::MatrixXf& actions);
  // Accumulates parameter gradients of a loss given its derivatives w.r.t. each sample's
  // log_prob, entropy and value of the last evaluate().
  void backward(const Eigen::VectorXf& d_log_prob, const Eigen::VectorXf& d_entropy,
                const Eigen::VectorXf& d_value);

  nn::ParamList params();
  void zero_grad();

  // The env action for one column of ActBatch::actions (Box actions clipped to the bounds).
  Action env_action(const Eigen::Ref<const Eigen::VectorXf>& column) const;

  int observation_size() const { return obs_size_; }
  int action_dim() const { return action_dim_; }
  // The deterministic policy as a policy program (policy_program.hpp) for observations of `space`.
  PolicyProgram policy_program(const std::string& algorithm, const ObservationSpace& space) const;
  // "normalize_observations": applied to the observations of every pass (off by default).
  ObservationNormalizer& normalizer() { return normalizer_; }
  const ObservationNormalizer& normalizer() const { return normalizer_; }
  bool discrete() const { return discrete_; }

  // ---- TRPO: the policy on its own, over the last evaluate() batch. Needs separate actor and
  // critic networks (rdsim::Error with a shared trunk or a CNN). ----
  // The policy's parameters (policy head, then log std for Box actions) and the value head's.
  nn::ParamList policy_params();
  nn::ParamList value_params();
  // The action distributions of the last evaluate() batch: logits (or Gaussian means) and log std.
  struct Distributions {
    Eigen::MatrixXf head;
    Eigen::VectorXf log_std;
  };
  Distributions distributions() const;
  // Mean over the batch of KL(old || the last evaluate()'s distributions).
  double mean_kl(const Distributions& old) const;
  // The Fisher information of the batch's action distributions w.r.t. policy_params() (the
  // Hessian of mean_kl at old == current), times `direction` (laid out as flatten_values(policy_params())).
  // Overwrites the policy head's gradients.
  Eigen::VectorXf fisher_vector_product(const Eigen::VectorXf& direction);

private:
  const Eigen::MatrixXf& features_infer(const Eigen::MatrixXf& obs);

  bool discrete_;
  int obs_size_;
  int action_dim_;
  int policy_outputs_;
  nn::Activation activation_;
  // The shared trunk (null when actor and critic are separate MLPs): obs -> features before the
  // activation; an MLP's last hidden layer, or for pixels a CNN's last fc layer.
  std::unique_ptr<nn::Network> trunk_;
  std::string trunk_prefix_;  // its parameters' names: "trunk." (MLP) or "cnn." (model files use them)
  nn::Mlp policy_;  // -> logits or Gaussian mean
  nn::Mlp value_;   // -> V
  nn::Tensor log_std_;
  Eigen::VectorXf low_, high_;
  float input_scale_ = 1.0f;
  ObservationNormalizer normalizer_;
  Eigen::MatrixXf infer_input_, eval_input_;  // standardised or scaled observations (input_scale != 1)
  // training caches
  Eigen::MatrixXf trunk_pre_, features_;
  Eigen::VectorXi eval_discrete_;
  Eigen::MatrixXf eval_actions_;
  std::unique_ptr<nn::Categorical> eval_categorical_;
  std::unique_ptr<nn::DiagGaussian> eval_gaussian_;
  PolicyEval eval_;
  Eigen::MatrixXf infer_features_;
};

}  // namespace rdsim
