// Augmented random search, "V2-t" (Mania, Guy & Recht 2018): a deterministic policy (linear by
// default) on observations standardised by their running statistics; each update draws n_delta
// directions delta ~ N(0, I), evaluates theta + nu delta and theta - nu delta for whole episodes
// (the population step, population.hpp), keeps the n_top directions with the best
// max(r+, r-), and moves theta += alpha / (n_top sigma_R) sum (r+ - r-) delta, sigma_R the std of
// the 2 n_top returns used. The observation statistics are updated with the states seen during
// the update, after it (the policies of one update all see the same standardisation).
#include "rdsim/algorithms/ars.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "rdsim/algorithms/policy_search.hpp"
#include "memory_footprint.hpp"

namespace rdsim {
namespace {

class Ars final : public PolicySearch {
public:
  Ars(const ArsConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
      const std::string& where)
      : PolicySearch(spec, network, config.zero_init, config.normalize_observations, seed, "ars", where), cfg_(config) {}

  std::string name() const override { return "ars"; }
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;

private:
  ArsConfig cfg_;
};

Metrics Ars::update(VecEnv& envs, const TrainProgress& /*progress*/) {
  const int n = cfg_.n_delta;
  const int top = cfg_.n_top > 0 ? cfg_.n_top : n;
  const auto nu = static_cast<float>(cfg_.delta_std);
  Eigen::VectorXf theta = policy_.parameters();
  // Directions and the 2n candidates theta + nu delta_k (even) and theta - nu delta_k (odd).
  std::vector<Eigen::VectorXf> deltas(static_cast<std::size_t>(n)), candidates;
  for (auto& d : deltas) {
    d.resize(theta.size());
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = static_cast<float>(rng_.normal());
    candidates.push_back(theta + nu * d);
    candidates.push_back(theta - nu * d);
  }
  const PopulationResult result = evaluate(envs, candidates, cfg_.episodes_per_candidate);

  // The top directions by max(r+, r-); ties keep the draw order.
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const auto best = [&](int k) { return std::max(result.returns[2 * k], result.returns[2 * k + 1]); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return best(a) > best(b); });
  double mean = 0.0;
  for (int k = 0; k < top; ++k) mean += result.returns[2 * order[k]] + result.returns[2 * order[k] + 1];
  mean /= 2.0 * top;
  double var = 0.0;
  for (int k = 0; k < top; ++k)
    for (int s = 0; s < 2; ++s) var += std::pow(result.returns[2 * order[k] + s] - mean, 2);
  const double sigma_r = std::sqrt(var / (2.0 * top));
  Eigen::VectorXd step = Eigen::VectorXd::Zero(theta.size());
  for (int k = 0; k < top; ++k) {
    const int d = order[static_cast<std::size_t>(k)];
    step += (result.returns[2 * d] - result.returns[2 * d + 1]) * deltas[static_cast<std::size_t>(d)].cast<double>();
  }
  step *= cfg_.learning_rate / (top * sigma_r + 1e-6);
  theta += step.cast<float>();
  policy_.set_parameters(theta);

  Metrics m = return_metrics(result);
  m.emplace_back("return_std", sigma_r);
  m.emplace_back("step_norm", step.norm());
  m.emplace_back("parameter_norm", theta.norm());
  m.emplace_back("observations_seen", static_cast<double>(normalizer_.count()));
  return m;
}

}  // namespace

std::unique_ptr<Algorithm> make_ars(const ArsConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where) {
  return std::make_unique<Ars>(config, network, seed, spec, where);
}

// 2 x n_delta perturbed parameter vectors.
void estimate_memory(const ArsConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  memory::policy_search(c.network, spec, num_envs, 2.0 * p.n_delta, false, "ars.n_delta", e);
}

}  // namespace rdsim
