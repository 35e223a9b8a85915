#include <catch2/catch.hpp>

#include "rdsim/algorithms/random.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "algorithm_checks.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

Setup random_setup(std::uint64_t seed) {
  Setup c;
  c.algorithm = "random";
  c.seed = seed;
  c.random.n_steps = 50;
  return c;
}

}  // namespace

TEST_CASE("the random agent acts uniformly in the action space and learns nothing", "[random]") {
  const Setup setup = random_setup(1);
  auto discrete = make_algorithm(setup, toy::SignEnv(true).spec());
  CHECK(discrete->name() == "random");
  Rng rng(3);
  Observation o;
  o.values = toy::vec({1.0f, 0.0f});
  int ones = 0;
  for (int k = 0; k < 4000; ++k) ones += discrete->act(o, true, rng).index;
  CHECK(std::abs(ones - 2000) < 200);  // ~6 standard deviations

  Spec box = toy::SignEnv(false).spec();
  box.action.low = toy::vec({-2.0f, 5.0f});
  box.action.high = toy::vec({2.0f, 6.0f});
  auto continuous = make_algorithm(setup, box);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int k = 0; k < 4000; ++k) {
    const Eigen::VectorXf a = continuous->act(o, false, rng).values;
    REQUIRE(a.size() == 2);
    CHECK((a.array() >= box.action.low.array()).all());
    CHECK((a.array() <= box.action.high.array()).all());
    sum += a.cast<double>();
  }
  CHECK(sum[0] / 4000 == Approx(0.0).margin(0.1));
  CHECK(sum[1] / 4000 == Approx(5.5).margin(0.03));

  VecEnv envs(toy::make_envs(3, true), 1);
  const std::string before = checks::weights(*discrete);
  const auto metrics = checks::train(*discrete, envs, 1000, 1000);
  CHECK(envs.timesteps() == 1002);  // n_steps of 3 envs per update, the last one cut at the goal
  CHECK(metrics.size() == 7);
  CHECK(checks::weights(*discrete) == before);
  CHECK(envs.episodes().stats().mean_return == Approx(5.0).margin(1.0));  // half the actions are right
}

TEST_CASE("the random agent: same seed, same run, checkpoints resume exactly, models round-trip", "[random][checkpoint]") {
  const Setup setup = random_setup(2);
  const checks::EnvFactory envs = [] { return toy::make_envs(2, false); };
  checks::same_seed_same_run(setup, envs, 300);
  checks::resume_is_exact(setup, envs, 200, 500, 1000);
}
