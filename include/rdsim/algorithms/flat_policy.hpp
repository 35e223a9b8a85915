#pragma once
#include <Eigen/Core>
#include <string>

#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/running_normalizer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/nn/mlp.hpp"

// The deterministic policy of the search methods (ARS, CMA-ES), whose parameters are one flat
// vector: an nn::Mlp with network.hidden_sizes and network.activation ([] = a linear policy, as
// in the ARS paper) on the observations, standardised by a RunningNormalizer when one is given,
// then times network.input_scale. Discrete actions: the largest output; Box actions: the outputs
// clipped to the bounds.
namespace rdsim {

struct PolicyProgram;  // policy_program.hpp

class FlatPolicy {
public:
  // Zero parameters when `zero_init` (ARS's start), else the Mlp's orthogonal init from `init`.
  // rdsim::Error naming `where` for pixel observations or an env whose episodes need not end
  // (a candidate is judged by whole episodes).
  FlatPolicy(const Spec& spec, const NetworkConfig& network, bool zero_init, Rng& init, const std::string& algorithm,
             const std::string& where);

  long long size() const { return size_; }
  int observation_size() const { return observation_size_; }
  Eigen::VectorXf parameters();
  void set_parameters(const Eigen::Ref<const Eigen::VectorXf>& flat);
  nn::ParamList params() { return net_.params(); }

  // The env action for one encoded observation.
  Action act(const Eigen::Ref<const Eigen::VectorXf>& observation, const RunningNormalizer* normalizer);
  // act()'s operations (policy_program.hpp), with `normalizer` as act() takes it.
  void add_policy_ops(PolicyProgram& program, const RunningNormalizer* normalizer) const;

private:
  Spec spec_;
  int observation_size_;
  nn::Mlp net_;
  long long size_;
  float input_scale_;
  Eigen::MatrixXf input_;
  Eigen::VectorXf normalized_;
};

}  // namespace rdsim
