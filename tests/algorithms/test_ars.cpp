#include <catch2/catch.hpp>

#include "rdsim/algorithms/ars.hpp"
#include "rdsim/algorithms/flat_policy.hpp"
#include "rdsim/algorithms/population.hpp"
#include "rdsim/algorithms/running_normalizer.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_checks.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

Setup ars_setup(std::uint64_t seed) {
  Setup c;
  c.algorithm = "ars";
  c.seed = seed;
  c.source = "sign_ars.json";
  c.network.hidden_sizes = {};  // linear, as the paper
  c.ars.n_delta = 4;
  c.ars.learning_rate = 0.05;
  c.ars.delta_std = 0.1;
  return c;
}

}  // namespace

TEST_CASE("running normaliser: mean and variance of what it saw, merging equals seeing all", "[ars]") {
  Rng rng(2);
  RunningNormalizer all(3), first(3), second(3);
  std::vector<Eigen::Vector3f> xs;
  for (int k = 0; k < 50; ++k) {
    xs.emplace_back(static_cast<float>(rng.normal(1, 2)), static_cast<float>(rng.normal(-3, 0.5)), 4.0f);
    all.add(xs.back());
    (k < 20 ? first : second).add(xs.back());
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), var = Eigen::Vector3d::Zero();
  for (const auto& x : xs) mean += x.cast<double>() / 50.0;
  for (const auto& x : xs) var += (x.cast<double>() - mean).cwiseAbs2() / 50.0;
  CHECK(all.mean().isApprox(mean, 1e-9));
  CHECK(all.variance().isApprox(var, 1e-9));
  first.merge(second);
  CHECK(first.count() == 50);
  CHECK(first.mean().isApprox(mean, 1e-9));
  CHECK(first.variance().isApprox(var, 1e-9));
  Eigen::VectorXf out(3);
  all.normalize(toy::vec({1.0f, -3.0f, 4.0f}), out);
  CHECK(out[0] == Approx((1.0 - mean[0]) / std::sqrt(var[0] + 1e-8)));
  CHECK(out[2] == Approx(0.0f));  // a constant input stays at zero
  RunningNormalizer empty(3);
  empty.normalize(toy::vec({1.0f, 2.0f, 3.0f}), out);
  CHECK(out == toy::vec({1.0f, 2.0f, 3.0f}));  // nothing seen yet: unchanged
}

TEST_CASE("population evaluation runs whole episodes per candidate and idle envs wait", "[ars]") {
  for (int num_envs : {1, 3}) {
    VecEnv envs(toy::make_envs(num_envs, true, 10), 5);
    NetworkConfig linear;
    linear.hidden_sizes = {};
    Rng init(0);
    FlatPolicy policy(envs.spec(), linear, true, init, "ars", "test");
    REQUIRE(policy.size() == 6);  // 2 outputs x 2 inputs + 2 biases
    // Weights (out x in, column-major), then biases: output 1 - output 0 = 2 s picks the rewarded action.
    Eigen::VectorXf perfect(6), backwards(6);
    perfect << -1, 1, 0, 0, 0, 0;
    backwards = -perfect;
    const std::vector<Eigen::VectorXf> candidates = {perfect, backwards, perfect, backwards, perfect};
    RunningNormalizer seen(2);
    const PopulationResult r = evaluate_population(envs, policy, candidates, 2, nullptr, &seen);
    INFO(num_envs << " envs");
    CHECK(r.returns == std::vector<double>{10, 0, 10, 0, 10});
    CHECK(r.steps == 5 * 2 * 10);  // every job is one 10-step episode; waiting envs take no steps
    CHECK(envs.timesteps() == r.steps);
    CHECK(seen.count() == r.steps);
    CHECK(envs.episodes().episodes() == 10);
  }
}

TEST_CASE("ARS learns the toy tasks with a linear policy", "[ars]") {
  for (bool discrete : {true, false}) {
    Setup setup = ars_setup(1);
    VecEnv envs(toy::make_envs(2, discrete), setup.seed);
    auto algo = make_algorithm(setup, envs.spec());
    CHECK(algo->name() == "ars");
    checks::train(*algo, envs, 200, 4000);
    const double early = envs.episodes().stats().mean_return;
    const auto metrics = checks::train(*algo, envs, 4000, 4000);
    const double late = metrics.back()[0].second;  // candidate_mean_return of the last update
    INFO((discrete ? "discrete" : "continuous") << ": candidates' mean return " << early << " -> " << late << " (best 10)");
    CHECK(late > (discrete ? 9.5 : 9.0));
    CHECK(late > early + (discrete ? 2.0 : 0.5));  // the zero policy already earns 7.5 on the continuous task
  }
}

TEST_CASE("ARS: same seed, same run, checkpoints resume exactly, models round-trip", "[ars][checkpoint]") {
  const Setup setup = ars_setup(2);
  checks::same_seed_same_run(setup, checks::sign_envs(3, true), 500);
  checks::resume_is_exact(setup, checks::sign_envs(3, false), 300, 800, 1000);
  VecEnv envs(toy::make_envs(2, false), 2);
  auto algo = make_algorithm(setup, envs.spec());
  checks::train(*algo, envs, 400, 400);
  checks::model_round_trips(setup, *algo, envs.spec(), toy::random_observation);
}
