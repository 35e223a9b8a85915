#pragma once
#include <Eigen/Core>
#include <vector>

#include "rdsim/algorithms/flat_policy.hpp"
#include "rdsim/algorithms/running_normalizer.hpp"
#include "rdsim/parallel/communicator.hpp"

// The population evaluation of the search methods (ARS, CMA-ES), as one separable step: given
// candidate parameter vectors, run whole episodes and return each candidate's mean return. It is
// the only place they touch envs, so a distributed evaluator (candidates split across MPI ranks,
// returns gathered: evaluate_population_on_ranks) replaces it without changing the algorithms.
namespace rdsim {

class VecEnv;

struct PopulationResult {
  std::vector<double> returns;  // mean episode return of each candidate, in candidate order
  long long steps = 0;          // env steps taken
};

// Every candidate runs `episodes` whole episodes with `policy` (its parameters replaced by the
// candidate's). Env e starts with job e (job j: candidate j / episodes); an env that ends an
// episode takes the next job, and waits (is not stepped) once none is left, so the result depends
// on the number of envs but not on timing. Envs must be at the start of an episode (as VecEnv
// leaves them after finishing one). The policy sees observations standardised by `normalizer`
// (when given, not changed); every observation it acts on is added to `seen` (when given).
PopulationResult evaluate_population(VecEnv& envs, FlatPolicy& policy, const std::vector<Eigen::VectorXf>& candidates,
                                     int episodes, const RunningNormalizer* normalizer, RunningNormalizer* seen);

// The population step of an MPI job (communicator.hpp): every rank holds the same candidates
// (drawn from the same seed), rank r evaluates the contiguous slice [r N / K, (r + 1) N / K) of
// them with its own envs, and one allgather hands every rank all N returns in candidate order,
// with `steps` the env steps of all ranks. `seen` (when given) ends with the observations of
// every rank, merged in rank order, so it too is identical on every rank. One rank: exactly
// evaluate_population.
PopulationResult evaluate_population_on_ranks(Communicator& comm, VecEnv& envs, FlatPolicy& policy,
                                              const std::vector<Eigen::VectorXf>& candidates, int episodes,
                                              const RunningNormalizer* normalizer, RunningNormalizer* seen);

}  // namespace rdsim
