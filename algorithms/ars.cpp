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

#include "rdsim/algorithms/flat_policy.hpp"
#include "rdsim/algorithms/observation_batch.hpp"
#include "rdsim/algorithms/population.hpp"
#include "rdsim/algorithms/running_normalizer.hpp"
#include "rdsim/algorithms/vec_env.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/nn/serialize.hpp"

namespace rdsim {
namespace {

Rng init_rng(std::uint64_t seed) { return Rng::derive(seed, rng_stream::network_init); }

class Ars final : public Algorithm {
public:
  Ars(const ArsConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
      const std::string& where)
      : cfg_(config),
        spec_(spec),
        policy_([&] {
          Rng init = init_rng(seed);
          return FlatPolicy(spec, network, config.zero_init, init, "ars", where);
        }()),
        theta_(policy_.parameters()),
        normalizer_(policy_.observation_size()),
        rng_(Rng::derive(seed, rng_stream::perturbations)) {}

  std::string name() const override { return "ars"; }
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;
  Action act(const Observation& observation, bool deterministic, Rng& rng) override;
  void save(std::ostream& out, bool training_state) const override;
  void load(std::istream& in, bool training_state, const std::string& source) override;

private:
  const RunningNormalizer* normalizer() const { return cfg_.normalize_observations ? &normalizer_ : nullptr; }

  ArsConfig cfg_;
  Spec spec_;
  FlatPolicy policy_;
  Eigen::VectorXf theta_;  // the policy's parameters
  RunningNormalizer normalizer_;
  Rng rng_;  // directions
};

Metrics Ars::update(VecEnv& envs, const TrainProgress& /*progress*/) {
  const int n = cfg_.n_delta;
  const int top = cfg_.n_top > 0 ? cfg_.n_top : n;
  const auto nu = static_cast<float>(cfg_.delta_std);
  // Directions and the 2n candidates theta + nu delta_k (even) and theta - nu delta_k (odd).
  std::vector<Eigen::VectorXf> deltas(static_cast<std::size_t>(n)), candidates;
  for (auto& d : deltas) {
    d.resize(theta_.size());
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = static_cast<float>(rng_.normal());
    candidates.push_back(theta_ + nu * d);
    candidates.push_back(theta_ - nu * d);
  }
  RunningNormalizer seen(policy_.observation_size());
  const PopulationResult result =
      evaluate_population(envs, policy_, candidates, cfg_.episodes_per_candidate, normalizer(), &seen);

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
  Eigen::VectorXd step = Eigen::VectorXd::Zero(theta_.size());
  for (int k = 0; k < top; ++k) {
    const int d = order[static_cast<std::size_t>(k)];
    step += (result.returns[2 * d] - result.returns[2 * d + 1]) * deltas[static_cast<std::size_t>(d)].cast<double>();
  }
  step *= cfg_.learning_rate / (top * sigma_r + 1e-6);
  theta_ += step.cast<float>();
  policy_.set_parameters(theta_);
  if (cfg_.normalize_observations) normalizer_.merge(seen);

  const auto [lo, hi] = std::minmax_element(result.returns.begin(), result.returns.end());
  return {{"candidate_mean_return", std::accumulate(result.returns.begin(), result.returns.end(), 0.0) /
                                        static_cast<double>(result.returns.size())},
          {"candidate_min_return", *lo},
          {"candidate_max_return", *hi},
          {"return_std", sigma_r},
          {"step_norm", step.norm()},
          {"parameter_norm", theta_.norm()},
          {"observations_seen", static_cast<double>(normalizer_.count())}};
}

Action Ars::act(const Observation& observation, bool /*deterministic*/, Rng& /*rng*/) {
  // ARS's policy is deterministic: stochastic acting is the same.
  Eigen::VectorXf obs(policy_.observation_size());
  encode_observation(observation, spec_.observation, obs);
  return policy_.act(obs, normalizer());
}

void Ars::save(std::ostream& out, bool training_state) const {
  auto& self = const_cast<Ars&>(*this);  // params() hands out mutable views; saving only reads them
  nn::save_params(self.policy_.params(), out);
  normalizer_.save(out);
  if (!training_state) return;
  write_string(out, rng_to_bytes(rng_));
}

void Ars::load(std::istream& in, bool training_state, const std::string& source) {
  nn::load_params(policy_.params(), in, source);
  theta_ = policy_.parameters();
  normalizer_.load(in, source);
  if (!training_state) return;
  rng_ = rng_from_bytes(read_string(in, source), source);
}

}  // namespace

std::unique_ptr<Algorithm> make_ars(const ArsConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where) {
  return std::make_unique<Ars>(config, network, seed, spec, where);
}

}  // namespace rdsim
