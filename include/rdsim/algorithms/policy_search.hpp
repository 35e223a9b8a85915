#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/flat_policy.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/population.hpp"
#include "rdsim/algorithms/running_normalizer.hpp"
#include "rdsim/core/rng.hpp"

// What the search methods (ARS, CMA-ES) share: a deterministic FlatPolicy holding the current
// parameters, optional running observation statistics, the random stream of their
// perturbations, the population step, acting, and the model/checkpoint layout. Each method adds
// only how it proposes candidates and moves its parameters (update()).
namespace rdsim {

class PolicySearch : public Algorithm {
public:
  // The policy is deterministic: stochastic acting is the same as deterministic.
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  PolicyProgram policy_program() const override;
  // Under MPI the ranks share the population (evaluate()): every rank draws the same candidates
  // from the same stream, evaluates its slice and makes the same update from all returns.
  bool data_parallel() const override { return true; }
  bool lockstep() const override { return false; }
  long long step_multiple(int) const override { return 0; }  // whole episodes
  // Model: the policy's parameters and the observation statistics. Checkpoint: those, the
  // perturbation stream and the method's own state (save_search).
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;
  // What the ranks of an MPI job share and compare: everything a checkpoint holds (parameters,
  // statistics, the perturbation stream and the method's state), since every rank draws the
  // same candidates. Rank 0's replace the others' at the start (their seeds differ).
  void save_all_weights(std::ostream& out) const override { save(out, true); }
  void load_all_weights(std::istream& in, const std::string& source) override { load(in, true, source); }

protected:
  PolicySearch(const Spec& spec, const NetworkConfig& network, bool zero_init, bool normalize_observations,
               std::uint64_t seed, const std::string& algorithm, const std::string& where);

  // The population step (population.hpp; spread over the ranks of an MPI job) with the current
  // observation statistics, which then take in the states the candidates saw on every rank (all candidates of one update see the same
  // standardisation, as ARS V2).
  PopulationResult evaluate(VecEnv& envs, const std::vector<Eigen::VectorXf>& candidates, int episodes);
  // The candidates' mean, lowest and highest returns, the first metrics of every search method.
  static Metrics return_metrics(const PopulationResult& result);

  virtual void save_search(std::ostream& /*out*/) const {}
  virtual void load_search(std::istream& /*in*/, const std::string& /*source*/) {}

  Spec spec_;
  FlatPolicy policy_;  // holds the current parameters between updates (what act() and model.bin use)
  RunningNormalizer normalizer_;
  bool normalize_observations_;
  Rng rng_;  // perturbations
};

}  // namespace rdsim
