#include "rdsim/algorithms/population.hpp"

#include <algorithm>
#include <cstddef>

#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

PopulationResult evaluate_population(VecEnv& envs, FlatPolicy& policy, const std::vector<Eigen::VectorXf>& candidates,
                                     int episodes, const RunningNormalizer* normalizer, RunningNormalizer* seen) {
  if (episodes < 1) throw Error("evaluate_population: episodes must be positive");
  const int n = envs.size();
  const long long jobs = static_cast<long long>(candidates.size()) * episodes;
  const long long start = envs.timesteps();
  std::vector<long long> job(static_cast<std::size_t>(n), -1);  // the job each env runs; -1: none left
  long long next_job = 0;
  for (auto& j : job) j = next_job < jobs ? next_job++ : -1;

  std::vector<double> sums(candidates.size(), 0.0), running(static_cast<std::size_t>(n), 0.0);
  std::vector<Action> actions(static_cast<std::size_t>(n));
  std::vector<bool> active(static_cast<std::size_t>(n));
  Eigen::VectorXf obs(policy.observation_size());
  long long loaded = -1;  // candidate whose parameters the policy holds
  for (bool any = true; any;) {
    any = false;
    for (int e = 0; e < n; ++e) {
      const auto k = static_cast<std::size_t>(e);
      active[k] = job[k] >= 0;
      if (!active[k]) continue;
      any = true;
      const long long candidate = job[k] / episodes;
      if (candidate != loaded) {
        policy.set_parameters(candidates[static_cast<std::size_t>(candidate)]);
        loaded = candidate;
      }
      encode_observation(envs.observations(), e, obs);
      if (seen) seen->add(obs);
      actions[k] = policy.act(obs, normalizer);
    }
    if (!any) break;
    const std::vector<EnvStep>& steps = envs.step(actions, active);
    for (int e = 0; e < n; ++e) {
      const auto k = static_cast<std::size_t>(e);
      if (!active[k]) continue;
      running[k] += steps[k].reward;
      if (!steps[k].done()) continue;
      sums[static_cast<std::size_t>(job[k] / episodes)] += running[k];
      running[k] = 0.0;
      job[k] = next_job < jobs ? next_job++ : -1;
    }
  }
  PopulationResult result;
  result.returns.resize(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c) result.returns[c] = sums[c] / episodes;
  result.steps = envs.timesteps() - start;
  return result;
}

PopulationResult evaluate_population_on_ranks(Communicator& comm, VecEnv& envs, FlatPolicy& policy,
                                              const std::vector<Eigen::VectorXf>& candidates, int episodes,
                                              const RunningNormalizer* normalizer, RunningNormalizer* seen) {
  const std::size_t n = candidates.size(), ranks = static_cast<std::size_t>(comm.size());
  if (ranks == 1) return evaluate_population(envs, policy, candidates, episodes, normalizer, seen);
  const auto first = [&](std::size_t r) { return r * n / ranks; };  // rank r's first candidate
  const auto rank = static_cast<std::size_t>(comm.rank());
  const std::vector<Eigen::VectorXf> mine(candidates.begin() + static_cast<std::ptrdiff_t>(first(rank)),
                                          candidates.begin() + static_cast<std::ptrdiff_t>(first(rank + 1)));
  RunningNormalizer own(policy.observation_size());
  const PopulationResult local = evaluate_population(envs, policy, mine, episodes, normalizer, seen ? &own : nullptr);
  if (seen) *seen = merge_over_ranks(comm, own);

  // One slot per rank: its returns (padded to the largest slice) and, last, its steps.
  const std::size_t slot = (n + ranks - 1) / ranks + 1;
  std::vector<double> send(slot, 0.0), all(slot * ranks);
  std::copy(local.returns.begin(), local.returns.end(), send.begin());
  send.back() = static_cast<double>(local.steps);  // exact below 2^53 steps
  comm.allgather(send.data(), slot, all.data());
  PopulationResult result;
  for (std::size_t r = 0; r < ranks; ++r) {
    const double* at = all.data() + r * slot;
    result.returns.insert(result.returns.end(), at, at + (first(r + 1) - first(r)));
    result.steps += static_cast<long long>(at[slot - 1]);
  }
  return result;
}

}  // namespace rdsim
