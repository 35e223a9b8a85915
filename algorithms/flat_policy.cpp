#include "rdsim/algorithms/flat_policy.hpp"

#include <cmath>

#include "rdsim/policy/policy_program.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/param.hpp"

namespace rdsim {
namespace {

const Spec& checked_spec(const Spec& spec, const std::string& algorithm, const std::string& where) {
  if (spec.observation.type != ObsType::Float32)
    throw Error(where + ": algorithm: \"" + algorithm + "\" needs vector observations, env \"" + spec.env_name +
                "\" gives pixels (use env.observation \"ground_truth\")");
  if (spec.max_episode_steps <= 0)
    throw Error(where + ": algorithm: \"" + algorithm + "\" judges candidates by whole episodes; env \"" +
                spec.env_name + "\" has no step limit");
  return spec;
}

}  // namespace

FlatPolicy::FlatPolicy(const Spec& spec, const NetworkConfig& network, bool zero_init, Rng& init,
                       const std::string& algorithm, const std::string& where)
    : spec_(checked_spec(spec, algorithm, where)),
      observation_size_(observation_input_size(spec.observation)),
      net_({observation_size_, network.hidden_sizes, spec.action.discrete ? spec.action.n : spec.action.dim(),
            nn::activation_from_string(network.activation, where + ": network.activation")},
           1.0f, init),
      size_(nn::parameter_count(net_.params())),
      input_scale_(static_cast<float>(network.input_scale)),
      input_(observation_size_, 1),
      normalized_(observation_size_) {
  if (zero_init) set_parameters(Eigen::VectorXf::Zero(size_));
}

Eigen::VectorXf FlatPolicy::parameters() { return nn::flatten_values(net_.params()); }

void FlatPolicy::set_parameters(const Eigen::Ref<const Eigen::VectorXf>& flat) { nn::assign_values(net_.params(), flat); }

Action FlatPolicy::act(const Eigen::Ref<const Eigen::VectorXf>& observation, const RunningNormalizer* normalizer) {
  if (normalizer)
    normalizer->normalize(observation, normalized_);
  else
    normalized_ = observation;
  input_.col(0) = normalized_ * input_scale_;
  const Eigen::MatrixXf& out = net_.infer(input_);
  if (spec_.action.discrete) {
    Eigen::Index best;
    out.col(0).maxCoeff(&best);
    return Action::discrete(static_cast<int>(best));
  }
  return Action::continuous(out.col(0).cwiseMax(spec_.action.low).cwiseMin(spec_.action.high));
}

void FlatPolicy::add_policy_ops(PolicyProgram& program, const RunningNormalizer* normalizer) const {
  program.input_size = observation_size_;
  program.discrete = spec_.action.discrete;
  program.action_size = spec_.action.discrete ? 1 : spec_.action.dim();
  if (normalizer && normalizer->count() >= 2) {
    // RunningNormalizer::normalize: in double, not clipped (here in float: within a few ulps)
    const Eigen::VectorXd inverse_std = (normalizer->variance().array() + 1e-8).sqrt().inverse();
    program.standardize(normalizer->mean().cast<float>(), inverse_std.cast<float>(), INFINITY);
  }
  program.scale(input_scale_);
  program.mlp(net_);
  if (spec_.action.discrete)
    program.argmax();
  else
    program.clip(spec_.action.low, spec_.action.high);
}

}  // namespace rdsim
