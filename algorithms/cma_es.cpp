// CMA-ES (Hansen & Ostermeier 2001; Hansen's 2016 tutorial) searching the parameters of a small
// deterministic policy (FlatPolicy: linear by default). A generation: ask lambda candidates
// from N(mean, sigma^2 C), evaluate each for whole episodes (the population step,
// population.hpp), tell the strategy their returns: the mean moves to the weighted best half,
// the evolution paths and C adapt (rank-one + rank-mu), sigma adapts by path length.
#include "rdsim/algorithms/cma_es.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "rdsim/algorithms/policy_search.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "memory_footprint.hpp"

namespace rdsim {

namespace cma {

Strategy::Strategy(const Eigen::VectorXd& mean, double sigma, int population)
    : mean_(mean), sigma_(sigma) {
  const int n = dimension();
  if (n < 1) throw Error("cma::Strategy: needs at least one parameter");
  lambda_ = population > 0 ? population : 4 + static_cast<int>(std::floor(3.0 * std::log(n)));
  lambda_ = std::max(lambda_, 2);
  set_constants();
  p_sigma_ = Eigen::VectorXd::Zero(n);
  p_c_ = Eigen::VectorXd::Zero(n);
  c_ = Eigen::MatrixXd::Identity(n, n);
  b_ = Eigen::MatrixXd::Identity(n, n);
  d_ = Eigen::VectorXd::Ones(n);
}

void Strategy::set_constants() {
  const double n = dimension();
  mu_ = lambda_ / 2;
  weights_.resize(mu_);
  for (int i = 0; i < mu_; ++i) weights_[i] = std::log((lambda_ + 1) / 2.0) - std::log(i + 1.0);
  weights_ /= weights_.sum();
  mu_eff_ = 1.0 / weights_.squaredNorm();
  c_sigma_ = (mu_eff_ + 2.0) / (n + mu_eff_ + 5.0);
  d_sigma_ = 1.0 + 2.0 * std::max(0.0, std::sqrt((mu_eff_ - 1.0) / (n + 1.0)) - 1.0) + c_sigma_;
  c_c_ = (4.0 + mu_eff_ / n) / (n + 4.0 + 2.0 * mu_eff_ / n);
  c_1_ = 2.0 / ((n + 1.3) * (n + 1.3) + mu_eff_);
  c_mu_ = std::min(1.0 - c_1_, 2.0 * (mu_eff_ - 2.0 + 1.0 / mu_eff_) / ((n + 2.0) * (n + 2.0) + mu_eff_));
  chi_n_ = std::sqrt(n) * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n));
}

void Strategy::decompose() {
  // Symmetrise against rounding, then C = B diag(D^2) B^T.
  c_ = 0.5 * (c_ + c_.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(c_);
  b_ = eig.eigenvectors();
  d_ = eig.eigenvalues().cwiseMax(1e-20).cwiseSqrt();
}

std::vector<Eigen::VectorXd> Strategy::ask(Rng& rng) {
  const int n = dimension();
  std::vector<Eigen::VectorXd> candidates(static_cast<std::size_t>(lambda_));
  y_.assign(static_cast<std::size_t>(lambda_), Eigen::VectorXd());
  Eigen::VectorXd z(n);
  for (int k = 0; k < lambda_; ++k) {
    for (int i = 0; i < n; ++i) z[i] = rng.normal();
    y_[static_cast<std::size_t>(k)] = b_ * d_.cwiseProduct(z);
    candidates[static_cast<std::size_t>(k)] = mean_ + sigma_ * y_[static_cast<std::size_t>(k)];
  }
  return candidates;
}

void Strategy::tell(const std::vector<double>& fitness) {
  if (fitness.size() != y_.size() || y_.empty()) throw Error("cma::Strategy::tell: one fitness per candidate of the last ask()");
  const int n = dimension();
  std::vector<int> order(static_cast<std::size_t>(lambda_));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return fitness[a] > fitness[b]; });

  // Recombination: the mean moves by sigma times the weighted mean step of the best mu.
  Eigen::VectorXd y_w = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < mu_; ++i) y_w += weights_[i] * y_[static_cast<std::size_t>(order[i])];
  mean_ += sigma_ * y_w;

  // Evolution paths; C^-1/2 y_w = B D^-1 B^T y_w.
  ++generation_;
  const Eigen::VectorXd c_inv_sqrt_y = b_ * (b_.transpose() * y_w).cwiseQuotient(d_);
  p_sigma_ = (1.0 - c_sigma_) * p_sigma_ + std::sqrt(c_sigma_ * (2.0 - c_sigma_) * mu_eff_) * c_inv_sqrt_y;
  const double ps_norm = p_sigma_.norm();
  const bool h_sigma = ps_norm / std::sqrt(1.0 - std::pow(1.0 - c_sigma_, 2.0 * static_cast<double>(generation_))) <
                       (1.4 + 2.0 / (n + 1.0)) * chi_n_;
  p_c_ = (1.0 - c_c_) * p_c_ + (h_sigma ? std::sqrt(c_c_ * (2.0 - c_c_) * mu_eff_) : 0.0) * y_w;

  // Covariance: rank-one (p_c) plus rank-mu (the best steps).
  Eigen::MatrixXd rank_mu = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < mu_; ++i) {
    const Eigen::VectorXd& y = y_[static_cast<std::size_t>(order[i])];
    rank_mu.noalias() += weights_[i] * y * y.transpose();
  }
  const double lost = h_sigma ? 0.0 : c_c_ * (2.0 - c_c_);
  c_ = (1.0 - c_1_ - c_mu_) * c_ + c_1_ * (p_c_ * p_c_.transpose() + lost * c_) + c_mu_ * rank_mu;

  // Step size: longer paths than expected under random selection grow sigma.
  sigma_ *= std::exp((c_sigma_ / d_sigma_) * (ps_norm / chi_n_ - 1.0));
  decompose();
  y_.clear();
}

void Strategy::save(std::ostream& out) const {
  write_u32(out, static_cast<std::uint32_t>(dimension()));
  write_u32(out, static_cast<std::uint32_t>(lambda_));
  write_u64(out, static_cast<std::uint64_t>(generation_));
  write_f64(out, sigma_);
  const auto write_doubles = [&](const double* data, Eigen::Index count) {
    for (Eigen::Index i = 0; i < count; ++i) write_f64(out, data[i]);
  };
  write_doubles(mean_.data(), mean_.size());
  write_doubles(p_sigma_.data(), p_sigma_.size());
  write_doubles(p_c_.data(), p_c_.size());
  write_doubles(c_.data(), c_.size());
}

void Strategy::load(std::istream& in, const std::string& source) {
  const std::uint32_t n = read_u32(in, source);
  if (n != static_cast<std::uint32_t>(dimension()))
    throw Error(source + ": CMA-ES state of " + std::to_string(n) + " parameters, expected " +
                std::to_string(dimension()) + " (a different network?)");
  const auto lambda = static_cast<int>(read_u32(in, source));
  if (lambda != lambda_) throw Error(source + ": CMA-ES population " + std::to_string(lambda) + ", expected " + std::to_string(lambda_));
  const std::uint64_t generation_bits = read_u64(in, source);
  const double sigma = read_f64(in, source);
  if (generation_bits > (1ull << 50) || !std::isfinite(sigma) || sigma <= 0.0)
    throw Error(source + ": CMA-ES state is damaged (generation or step size out of range)");
  const auto generation = static_cast<long long>(generation_bits);
  const auto read_doubles = [&](Eigen::Index count) {
    Eigen::VectorXd v(count);
    for (Eigen::Index i = 0; i < count; ++i) v[i] = read_f64(in, source);
    return v;
  };
  Eigen::VectorXd mean = read_doubles(n), p_sigma = read_doubles(n), p_c = read_doubles(n);
  const Eigen::VectorXd c = read_doubles(static_cast<Eigen::Index>(n) * n);
  if (!mean.allFinite() || !p_sigma.allFinite() || !p_c.allFinite() || !c.allFinite())
    throw Error(source + ": CMA-ES state holds values that are not finite (damaged file?)");
  generation_ = generation;
  sigma_ = sigma;
  mean_ = mean;
  p_sigma_ = p_sigma;
  p_c_ = p_c;
  c_ = Eigen::Map<const Eigen::MatrixXd>(c.data(), n, n);
  decompose();
}

}  // namespace cma

namespace {

class CmaEs final : public PolicySearch {
public:
  CmaEs(const CmaEsConfig& config, const NetworkConfig& network, std::uint64_t seed, const Spec& spec,
        const std::string& where)
      : PolicySearch(spec, network, config.zero_init, config.normalize_observations, seed, "cma_es", where),
        cfg_(config) {
    if (policy_.size() > cma::max_parameters)
      throw Error(where + ": network.hidden_sizes: the policy has " + std::to_string(policy_.size()) +
                  " parameters; cma_es keeps a full covariance matrix and allows at most " +
                  std::to_string(cma::max_parameters) + " (use smaller hidden layers, [] for a linear policy, or ars)");
    strategy_ = cma::Strategy(policy_.parameters().cast<double>(), config.sigma, config.population_size);
  }

  std::string name() const override { return "cma_es"; }
  Metrics update(VecEnv& envs, const TrainProgress& progress) override;

protected:
  void save_search(std::ostream& out) const override { strategy_.save(out); }
  void load_search(std::istream& in, const std::string& source) override { strategy_.load(in, source); }

private:
  CmaEsConfig cfg_;
  cma::Strategy strategy_;
};

Metrics CmaEs::update(VecEnv& envs, const TrainProgress& /*progress*/) {
  std::vector<Eigen::VectorXf> candidates;
  for (const Eigen::VectorXd& x : strategy_.ask(rng_)) candidates.push_back(x.cast<float>());
  const PopulationResult result = evaluate(envs, candidates, cfg_.episodes_per_candidate);
  strategy_.tell(result.returns);
  policy_.set_parameters(strategy_.mean().cast<float>());

  Metrics m = return_metrics(result);
  m.emplace_back("sigma", strategy_.sigma());
  m.emplace_back("mean_norm", strategy_.mean().norm());
  m.emplace_back("generation", static_cast<double>(strategy_.generation()));
  return m;
}

}  // namespace

std::unique_ptr<Algorithm> make_cma_es(const CmaEsConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                       const Spec& spec, const std::string& where) {
  return std::make_unique<CmaEs>(config, network, seed, spec, where);
}

// lambda candidates (population_size, or CMA-ES's default from the parameter count) and the covariance.
void estimate_memory(const CmaEsConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e) {
  const double params = memory::mlp(observation_input_size(spec.observation), c.network.hidden_sizes,
                                    spec.action.discrete ? spec.action.n : spec.action.dim())
                            .params;
  const double lambda = p.population_size > 0 ? p.population_size : 4.0 + std::floor(3.0 * std::log(std::max(params, 1.0)));
  memory::policy_search(c.network, spec, num_envs, lambda, true, "cma_es.population_size", e);
}

}  // namespace rdsim
