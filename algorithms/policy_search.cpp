#include "rdsim/algorithms/policy_search.hpp"

#include <algorithm>
#include <numeric>

#include "rdsim/policy/policy_program.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/nn/serialize.hpp"

namespace rdsim {
namespace {

FlatPolicy make_policy(const Spec& spec, const NetworkConfig& network, bool zero_init, std::uint64_t seed,
                       const std::string& algorithm, const std::string& where) {
  Rng init = Rng::derive(seed, rng_stream::network_init);
  return FlatPolicy(spec, network, zero_init, init, algorithm, where);
}

}  // namespace

PolicySearch::PolicySearch(const Spec& spec, const NetworkConfig& network, bool zero_init, bool normalize_observations,
                           std::uint64_t seed, const std::string& algorithm, const std::string& where)
    : spec_(spec),
      policy_(make_policy(spec, network, zero_init, seed, algorithm, where)),
      normalizer_(policy_.observation_size()),
      normalize_observations_(normalize_observations),
      rng_(Rng::derive(seed, rng_stream::perturbations)) {}

PopulationResult PolicySearch::evaluate(VecEnv& envs, const std::vector<Eigen::VectorXf>& candidates, int episodes) {
  const Eigen::VectorXf current = policy_.parameters();
  RunningNormalizer seen(policy_.observation_size());
  PopulationResult result = evaluate_population_on_ranks(communicator(), envs, policy_, candidates, episodes,
                                                         normalize_observations_ ? &normalizer_ : nullptr, &seen);
  if (normalize_observations_) normalizer_.merge(seen);
  policy_.set_parameters(current);
  return result;
}

Metrics PolicySearch::return_metrics(const PopulationResult& result) {
  const auto [lo, hi] = std::minmax_element(result.returns.begin(), result.returns.end());
  return {{"candidate_mean_return",
           std::accumulate(result.returns.begin(), result.returns.end(), 0.0) / static_cast<double>(result.returns.size())},
          {"candidate_min_return", *lo},
          {"candidate_max_return", *hi}};
}

Action PolicySearch::act(const Observation& observation, bool /*deterministic*/, Rng& /*rng*/) {
  Eigen::VectorXf obs(policy_.observation_size());
  encode_observation(observation, spec_.observation, obs);
  return policy_.act(obs, normalize_observations_ ? &normalizer_ : nullptr);
}

PolicyProgram PolicySearch::policy_program() const {
  PolicyProgram program;
  program.algorithm = name();
  policy_.add_policy_ops(program, normalize_observations_ ? &normalizer_ : nullptr);
  return program;
}

void PolicySearch::save(std::ostream& out, bool training_state) const {
  auto& self = const_cast<PolicySearch&>(*this);  // params() hands out mutable views; saving only reads them
  nn::save_params(self.policy_.params(), out);
  normalizer_.save(out);
  if (!training_state) return;
  write_string(out, rng_to_bytes(rng_));
  save_search(out);
}

void PolicySearch::load(std::istream& in, bool training_state, const std::string& source) {
  nn::load_params(policy_.params(), in, source);
  normalizer_.load(in, source);
  if (!training_state) return;
  rng_ = rng_from_bytes(read_string(in, source), source);
  load_search(in, source);
}

}  // namespace rdsim
