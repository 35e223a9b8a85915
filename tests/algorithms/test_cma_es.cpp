#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>

#include "rdsim/algorithms/cma_es.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_checks.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

Setup cma_setup(std::uint64_t seed) {
  Setup c;
  c.algorithm = "cma_es";
  c.seed = seed;
  c.source = "sign_cma.json";
  c.network.hidden_sizes = {};
  c.cma_es.sigma = 0.5;
  return c;
}

// Runs the strategy on f (maximised) for `generations`; returns the final mean.
Eigen::VectorXd optimise(cma::Strategy& es, const std::function<double(const Eigen::VectorXd&)>& f, int generations) {
  Rng rng(7);
  for (int g = 0; g < generations; ++g) {
    std::vector<double> fitness;
    for (const Eigen::VectorXd& x : es.ask(rng)) fitness.push_back(f(x));
    es.tell(fitness);
  }
  return es.mean();
}

}  // namespace

TEST_CASE("CMA-ES finds the optimum of a sphere and of Rosenbrock's valley", "[cma_es]") {
  const Eigen::VectorXd target = (Eigen::VectorXd(5) << 1, -2, 0.5, 3, -1).finished();
  cma::Strategy sphere(Eigen::VectorXd::Zero(5), 1.0, 0);
  CHECK(sphere.population() == 4 + 4);  // 4 + floor(3 ln 5)
  const Eigen::VectorXd best = optimise(sphere, [&](const Eigen::VectorXd& x) { return -(x - target).squaredNorm(); }, 150);
  CHECK((best - target).norm() < 1e-4);
  CHECK(sphere.sigma() < 1e-3);  // the step size shrinks near the optimum

  cma::Strategy valley(Eigen::VectorXd::Zero(2), 0.5, 0);
  const Eigen::VectorXd rosen = optimise(valley, [](const Eigen::VectorXd& x) {
    return -(100.0 * std::pow(x[1] - x[0] * x[0], 2) + std::pow(1.0 - x[0], 2));
  }, 300);
  CHECK((rosen - Eigen::Vector2d(1.0, 1.0)).norm() < 1e-3);
}

TEST_CASE("CMA-ES adapts its covariance to the shape of the objective", "[cma_es]") {
  // An ellipsoid 100x steeper along x1 - x2 than along x1 + x2: C's long axis becomes x1 + x2.
  cma::Strategy es(Eigen::Vector2d(3.0, 1.0), 1.0, 0);
  optimise(es, [](const Eigen::VectorXd& x) {
    const double a = (x[0] - x[1]) / std::sqrt(2.0), b = (x[0] + x[1]) / std::sqrt(2.0);
    return -(100.0 * a * a + b * b);
  }, 40);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(es.covariance());
  const Eigen::Vector2d longest = eig.eigenvectors().col(1);
  CHECK(std::abs(longest.dot(Eigen::Vector2d(1.0, 1.0).normalized())) > 0.95);
  CHECK(eig.eigenvalues()[1] / eig.eigenvalues()[0] > 10.0);
}

TEST_CASE("CMA-ES learns the toy tasks with a linear policy", "[cma_es]") {
  for (bool discrete : {true, false}) {
    Setup setup = cma_setup(1);
    VecEnv envs(toy::make_envs(2, discrete), setup.seed);
    auto algo = make_algorithm(setup, envs.spec());
    CHECK(algo->name() == "cma_es");
    const auto metrics = checks::train(*algo, envs, 3000, 3000);
    const double best = metrics.back()[2].second;  // candidate_max_return
    const double mean = metrics.back()[0].second;
    INFO((discrete ? "discrete" : "continuous") << ": last generation mean " << mean << ", best " << best);
    CHECK(best > (discrete ? 9.99 : 9.5));
    CHECK(mean > (discrete ? 8.0 : 8.5));
  }
}

TEST_CASE("CMA-ES: same seed, same run, checkpoints resume exactly, models round-trip", "[cma_es][checkpoint]") {
  const Setup setup = cma_setup(2);
  checks::same_seed_same_run(setup, checks::sign_envs(2, true), 300);
  checks::resume_is_exact(setup, checks::sign_envs(2, false), 200, 600, 1000);
  VecEnv envs(toy::make_envs(2, false), 2);
  auto algo = make_algorithm(setup, envs.spec());
  checks::train(*algo, envs, 300, 300);
  checks::model_round_trips(setup, *algo, envs.spec(), toy::random_observation);
}

TEST_CASE("CMA-ES refuses policies beyond its parameter limit", "[cma_es]") {
  Setup setup = cma_setup(0);
  setup.network.hidden_sizes = {64, 64};  // 2*64+64 + 64*64+64 + 64*2+2 = 4482 parameters
  CHECK_THROWS_WITH(make_algorithm(setup, toy::SignEnv().spec()),
                    Catch::Contains("sign_cma.json") && Catch::Contains("4482") && Catch::Contains("2000"));
}
