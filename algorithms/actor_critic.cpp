#include "rdsim/algorithms/actor_critic.hpp"

#include <cmath>

#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

constexpr float hidden_gain = 1.41421356f;  // sqrt(2), the baselines' choice for hidden layers
constexpr float policy_gain = 0.01f;        // near-uniform initial policy
constexpr float value_gain = 1.0f;

// y = a(z), keeping z (the trunk's pre-activation output) for the backward pass.
void activate(const Eigen::MatrixXf& z, nn::Activation a, Eigen::MatrixXf& y) {
  y = z;
  nn::activate(y, a);
}

}  // namespace

bool is_image_space(const ObservationSpace& space) { return space.shape.size() == 3; }

nn::CnnShape cnn_shape(const CnnConfig& config, const ObservationSpace& space, int outputs, const std::string& where) {
  if (!is_image_space(space)) throw Error(where + ": a CNN needs image observations {height, width, channels}");
  const nn::ImageShape image{space.shape[0], space.shape[1], space.shape[2]};
  std::string preset = config.preset;
  if (preset == "auto") preset = image.height >= 84 && image.width >= 84 ? "nature" : "small";
  nn::CnnShape shape = nn::cnn_preset(preset, image, outputs, where + ".preset");
  if (!config.channels.empty()) {
    if (config.kernels.size() != config.channels.size() || config.strides.size() != config.channels.size())
      throw Error(where + ": channels, kernels and strides need the same length");
    shape.convs.clear();
    for (size_t i = 0; i < config.channels.size(); ++i)
      shape.convs.push_back({config.channels[i], config.kernels[i], config.strides[i], 0});
  }
  if (!config.fc.empty()) shape.hidden_sizes = config.fc;
  return shape;
}

nn::Cnn make_cnn(const nn::CnnShape& shape, float output_gain, Rng& rng, const std::string& where) {
  try {
    return nn::Cnn(shape, output_gain, rng);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

ActorCritic::ActorCritic(const Spec& spec, const NetworkConfig& config, Rng& rng)
    : discrete_(spec.action.discrete),
      obs_size_(observation_input_size(spec.observation)),
      action_dim_(spec.action.dim()),
      policy_outputs_(spec.action.discrete ? spec.action.n : spec.action.dim()),
      activation_(nn::activation_from_string(config.activation, "network.activation")) {
  if (obs_size_ <= 0) throw Error(spec.env_name + ": the env has an empty observation space");
  if (policy_outputs_ <= 0) throw Error(spec.env_name + ": the env has an empty action space");
  const bool pixels = is_image_space(spec.observation);
  if (config.input_scale != 1.0 && pixels)
    throw Error("network.input_scale: only for vector observations (pixels are already scaled to [0, 1]); expected 1");
  if (!(config.input_scale > 0.0 && std::isfinite(config.input_scale)))
    throw Error("network.input_scale: expected a positive number, got " + std::to_string(config.input_scale));
  input_scale_ = static_cast<float>(config.input_scale);
  int head_input = obs_size_;
  std::vector<int> head_hidden = config.hidden_sizes;
  if (pixels) {
    // The CNN is the shared trunk; its last fc layer (ReLU) feeds two linear heads.
    nn::CnnShape shape = cnn_shape(config.cnn, spec.observation, 1, "network.cnn");
    if (shape.hidden_sizes.empty()) throw Error("network.cnn.fc: expected at least one dense layer");
    shape.output_size = shape.hidden_sizes.back();
    shape.hidden_sizes.pop_back();
    trunk_ = std::make_unique<nn::Cnn>(make_cnn(shape, hidden_gain, rng, "network.cnn"));
    trunk_prefix_ = "cnn.";
    activation_ = nn::Activation::ReLU;
  } else if (config.shared && !config.hidden_sizes.empty()) {
    std::vector<int> trunk_hidden(config.hidden_sizes.begin(), config.hidden_sizes.end() - 1);
    trunk_ = std::make_unique<nn::Mlp>(nn::MlpShape{obs_size_, trunk_hidden, config.hidden_sizes.back(), activation_},
                                       hidden_gain, rng);
    trunk_prefix_ = "trunk.";
  }
  if (trunk_) {
    head_input = trunk_->output_size();
    head_hidden.clear();
  }
  policy_ = nn::Mlp({head_input, head_hidden, policy_outputs_, activation_}, policy_gain, rng, hidden_gain);
  value_ = nn::Mlp({head_input, head_hidden, 1, activation_}, value_gain, rng, hidden_gain);
  if (!discrete_) {
    log_std_ = nn::Tensor(action_dim_, 1);
    log_std_.value.setConstant(static_cast<float>(config.log_std_init));
    low_ = spec.action.low;
    high_ = spec.action.high;
  }
}

const Eigen::MatrixXf& ActorCritic::features_infer(const Eigen::MatrixXf& raw) {
  const Eigen::MatrixXf& obs = normalizer_.network_input(raw, input_scale_, infer_input_);
  if (!trunk_) return obs;
  activate(trunk_->infer(obs), activation_, infer_features_);
  return infer_features_;
}

void ActorCritic::act(const Eigen::MatrixXf& obs, bool deterministic, Rng& rng, ActBatch& out) {
  const Eigen::MatrixXf& f = features_infer(obs);
  const Eigen::MatrixXf& head = policy_.infer(f);
  if (discrete_) {
    const nn::Categorical dist(head);
    const Eigen::VectorXi a = deterministic ? dist.mode() : dist.sample(rng);
    out.actions = a.cast<float>().transpose();
    out.log_probs = dist.log_prob(a);
  } else {
    const nn::DiagGaussian dist(head, log_std_.value.col(0));
    out.actions = deterministic ? dist.mode() : dist.sample(rng);
    out.log_probs = dist.log_prob(out.actions);
  }
  out.values = value_.infer(f).row(0).transpose();
}

Eigen::VectorXf ActorCritic::predict_values(const Eigen::MatrixXf& obs) {
  return value_.infer(features_infer(obs)).row(0).transpose();
}

const PolicyEval& ActorCritic::evaluate(const Eigen::MatrixXf& raw, const Eigen::MatrixXf& actions) {
  const Eigen::MatrixXf& obs = normalizer_.network_input(raw, input_scale_, eval_input_);
  if (trunk_) {
    trunk_pre_ = trunk_->forward_borrowing(obs);  // obs lives until backward(): the header's contract
    activate(trunk_pre_, activation_, features_);
  }
  const Eigen::MatrixXf& f = trunk_ ? features_ : obs;
  const Eigen::MatrixXf& head = policy_.forward(f);
  if (discrete_) {
    eval_discrete_ = actions.row(0).transpose().array().round().cast<int>();
    eval_categorical_ = std::make_unique<nn::Categorical>(head);
    eval_.log_probs = eval_categorical_->log_prob(eval_discrete_);
    eval_.entropy = eval_categorical_->entropy();
  } else {
    eval_actions_ = actions;
    eval_gaussian_ = std::make_unique<nn::DiagGaussian>(head, log_std_.value.col(0));
    eval_.log_probs = eval_gaussian_->log_prob(eval_actions_);
    eval_.entropy = eval_gaussian_->entropy();
  }
  eval_.values = value_.forward(f).row(0).transpose();
  return eval_;
}

void ActorCritic::backward(const Eigen::VectorXf& d_log_prob, const Eigen::VectorXf& d_entropy,
                           const Eigen::VectorXf& d_value) {
  const bool entropy_term = d_entropy.size() > 0 && !d_entropy.isZero(0.0f);
  Eigen::MatrixXf d_head;
  if (discrete_) {
    d_head = eval_categorical_->log_prob_grad(eval_discrete_, d_log_prob);
    if (entropy_term) d_head += eval_categorical_->entropy_grad(d_entropy);
  } else {
    nn::DiagGaussian::Grad g = eval_gaussian_->log_prob_grad(eval_actions_, d_log_prob);
    d_head = std::move(g.mean);
    log_std_.grad.col(0) += g.log_std;
    if (entropy_term) log_std_.grad.col(0) += eval_gaussian_->entropy_grad_log_std(d_entropy);
  }
  const bool shared = trunk_ != nullptr;
  Eigen::MatrixXf d_features = policy_.backward(d_head, shared);
  const Eigen::MatrixXf d_features_value = value_.backward(d_value.transpose(), shared);
  if (shared) {
    d_features += d_features_value;
    nn::activation_backward(d_features, features_, activation_);
    trunk_->backward(d_features, false);
  }
}

nn::ParamList ActorCritic::params() {
  nn::ParamList list;
  if (trunk_) nn::append_params(list, trunk_->params(), trunk_prefix_);
  nn::append_params(list, policy_.params(), "policy.");
  nn::append_params(list, value_.params(), "value.");
  if (!discrete_) list.push_back(nn::param_of(log_std_, "log_std"));
  return list;
}

void ActorCritic::zero_grad() { nn::zero_grad(params()); }

PolicyProgram ActorCritic::policy_program(const std::string& algorithm, const ObservationSpace& space) const {
  PolicyProgram program;
  program.algorithm = algorithm;
  program.input_size = obs_size_;
  program.pixels = space.type == ObsType::UInt8 && is_image_space(space);  // Float32 images go in as values
  if (program.pixels) program.image_shape = space.shape;
  program.discrete = discrete_;
  program.action_size = discrete_ ? 1 : action_dim_;
  normalizer_.add_input_ops(program, input_scale_);
  // The trunk's output is activated (features_infer).
  if (const auto* mlp = dynamic_cast<const nn::Mlp*>(trunk_.get())) {
    program.mlp(*mlp);
    program.activate(activation_);
  } else if (const auto* cnn = dynamic_cast<const nn::Cnn*>(trunk_.get())) {
    program.cnn(*cnn);
    program.activate(activation_);
  }
  program.mlp(policy_);
  if (discrete_)
    program.argmax();  // the mode of the categorical distribution
  else if (low_.size() == action_dim_)
    program.clip(low_, high_);  // the Gaussian's mean, clipped to the Box (env_action)
  return program;
}

Action ActorCritic::env_action(const Eigen::Ref<const Eigen::VectorXf>& column) const {
  if (discrete_) return Action::discrete(static_cast<int>(std::lround(column[0])));
  Eigen::VectorXf v = column;
  if (low_.size() == v.size()) v = v.cwiseMax(low_).cwiseMin(high_);
  return Action::continuous(std::move(v));
}

namespace {
void require_separate(bool shared) {
  if (shared) throw Error("ActorCritic: the policy on its own needs separate actor and critic networks (network.shared false, no CNN)");
}
}  // namespace

nn::ParamList ActorCritic::policy_params() {
  require_separate(trunk_ != nullptr);
  nn::ParamList list;
  nn::append_params(list, policy_.params(), "policy.");
  if (!discrete_) list.push_back(nn::param_of(log_std_, "log_std"));
  return list;
}

nn::ParamList ActorCritic::value_params() {
  nn::ParamList list;
  nn::append_params(list, value_.params(), "value.");
  return list;
}

ActorCritic::Distributions ActorCritic::distributions() const {
  if (discrete_) return {eval_categorical_->log_probs(), {}};  // log-softmax: the same distribution as the logits
  return {eval_gaussian_->mean(), eval_gaussian_->log_std()};
}

double ActorCritic::mean_kl(const Distributions& old) const {
  if (discrete_) return nn::Categorical(old.head).kl_divergence(*eval_categorical_).cast<double>().mean();
  return nn::DiagGaussian(old.head, old.log_std).kl_divergence(*eval_gaussian_).cast<double>().mean();
}

Eigen::VectorXf ActorCritic::fisher_vector_product(const Eigen::VectorXf& direction) {
  require_separate(trunk_ != nullptr);
  const Eigen::Index head_params = nn::parameter_count(policy_.params());
  const Eigen::MatrixXf tangent = policy_.jvp(direction.head(head_params));
  const float inv_b = 1.0f / static_cast<float>(tangent.cols());
  // J^T (F J v) / batch through the policy head; F of a Gaussian w.r.t. log std is 2 per sample.
  const Eigen::MatrixXf f = discrete_ ? eval_categorical_->fisher_product(tangent) : eval_gaussian_->fisher_product_mean(tangent);
  policy_.zero_grad();
  policy_.backward(f * inv_b, false);
  Eigen::VectorXf out(direction.size());
  out.head(head_params) = nn::flatten_grads(policy_.params());
  if (!discrete_) out.tail(action_dim_) = 2.0f * direction.tail(action_dim_);
  return out;
}

}  // namespace rdsim
