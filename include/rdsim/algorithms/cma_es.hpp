#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/rng.hpp"

// The covariance matrix adaptation evolution strategy (algorithms/cma_es.cpp) over the
// parameters of a small policy.
namespace rdsim {

// The "cma_es" object of a training config. Defaults: Hansen's (population 4 + 3 ln n).
struct CmaEsConfig {
  int population_size = 0;
  double sigma = 0.5;
  bool zero_init = true;
  bool normalize_observations = false;
  int episodes_per_candidate = 1;
};

template <class V, class C>
  requires config::Describes<C, CmaEsConfig>
void describe(V& v, C& c) {
  v.field("population_size", c.population_size, config::Range{0, 100'000},
          "candidates per generation (lambda); 0 = 4 + floor(3 ln n) for n parameters");
  v.check(c.population_size == 0 || c.population_size >= 2, "population_size", "expected 0 (automatic) or at least 2");
  v.field("sigma", c.sigma, config::Range{1e-9, 1e6}, "initial step size (std of the first candidates around the mean)");
  v.field("zero_init", c.zero_init, "the first mean is all zeros, else the network's random init");
  v.field("normalize_observations", c.normalize_observations,
          "standardise observations by their running mean and std (as ARS V2)");
  v.field("episodes_per_candidate", c.episodes_per_candidate, config::Range{1, 10'000},
          "episodes averaged into each candidate's fitness");
}

// rdsim::Error naming `where` (the config file) for pixel observations or a policy with more
// parameters than cma::max_parameters.
std::unique_ptr<Algorithm> make_cma_es(const CmaEsConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                       const Spec& spec, const std::string& where);

}  // namespace rdsim

namespace rdsim::cma {

// The full covariance matrix costs n^2 memory and an O(n^3) eigendecomposition per generation:
// at 2,000 parameters that is 32 MB and about a second per generation on one core. Bigger
// policies should use ARS (linear in n).
inline constexpr long long max_parameters = 2000;

// The CMA-ES state and update of Hansen's tutorial ("The CMA Evolution Strategy: A Tutorial",
// 2016): weighted recombination of the best half, cumulative step-size adaptation, and the
// rank-one plus rank-mu covariance update. Maximises: higher fitness is better. In double.
class Strategy {
public:
  Strategy() = default;
  // `population` 0 = 4 + floor(3 ln n).
  Strategy(const Eigen::VectorXd& mean, double sigma, int population);

  int dimension() const { return static_cast<int>(mean_.size()); }
  int population() const { return lambda_; }
  const Eigen::VectorXd& mean() const { return mean_; }
  double sigma() const { return sigma_; }
  const Eigen::MatrixXd& covariance() const { return c_; }
  long long generation() const { return generation_; }

  // lambda candidates mean + sigma B D z, z ~ N(0, I) drawn from `rng`.
  std::vector<Eigen::VectorXd> ask(Rng& rng);
  // Updates from the fitness of the candidates of the last ask() (same order).
  void tell(const std::vector<double>& fitness);

  void save(std::ostream& out) const;
  // rdsim::Error naming `source` when the dimension differs or the stream ends early.
  void load(std::istream& in, const std::string& source);

private:
  void set_constants();
  void decompose();  // B, D from C

  Eigen::VectorXd mean_;
  double sigma_ = 1.0;
  int lambda_ = 0, mu_ = 0;
  Eigen::VectorXd weights_;
  double mu_eff_ = 0, c_sigma_ = 0, d_sigma_ = 0, c_c_ = 0, c_1_ = 0, c_mu_ = 0, chi_n_ = 0;
  Eigen::VectorXd p_sigma_, p_c_;
  Eigen::MatrixXd c_, b_;  // covariance, its eigenvectors
  Eigen::VectorXd d_;      // square roots of its eigenvalues
  long long generation_ = 0;
  std::vector<Eigen::VectorXd> y_;  // (candidate - mean) / sigma of the last ask()
};

}  // namespace rdsim::cma
