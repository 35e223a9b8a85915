#include <catch2/catch.hpp>

#include "rdsim/algorithms/off_policy.hpp"
#include "rdsim/algorithms/sac.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_checks.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

// The continuous sign task (toy_env.hpp): reward 1 - (a - 0.5 s)^2, best action 0.5 s.
Setup sac_setup(std::uint64_t seed) {
  Setup c;
  c.algorithm = "sac";
  c.seed = seed;
  c.source = "sign_sac.json";
  c.network.hidden_sizes = {32, 32};
  c.network.activation = "relu";
  c.sac.learning_rate = 3e-3;
  c.sac.batch_size = 64;
  c.sac.buffer_size = 5000;
  c.sac.learning_starts = 200;
  c.sac.gamma = 0.5;  // the best action does not depend on the future: a short horizon learns fast
  return c;
}

}  // namespace

TEST_CASE("SAC soft TD targets: minimum of the target critics minus the entropy term, no bootstrap after termination", "[sac]") {
  const Eigen::VectorXf rewards = (Eigen::VectorXf(2) << 1.0f, 2.0f).finished();
  const Eigen::VectorXf terminated = (Eigen::VectorXf(2) << 0.0f, 1.0f).finished();
  const Eigen::VectorXf next_q = (Eigen::VectorXf(2) << 4.0f, 9.0f).finished();
  const Eigen::VectorXf next_log_prob = (Eigen::VectorXf(2) << -1.0f, 3.0f).finished();
  const Eigen::VectorXf y = sac::soft_td_targets(rewards, terminated, next_q, next_log_prob, 0.2f, 0.9f);
  CHECK(y[0] == Approx(1.0f + 0.9f * (4.0f + 0.2f)));
  CHECK(y[1] == Approx(2.0f));
}

TEST_CASE("SAC moves the policy towards the best action of a toy task", "[sac]") {
  const Setup setup = sac_setup(1);
  VecEnv envs(toy::make_envs(2, false), setup.seed);
  auto algo = make_algorithm(setup, envs.spec());
  CHECK(algo->name() == "sac");
  Rng rng(0);
  const float before = algo->act(toy::observation(1.0f), true, rng).values[0];
  const auto metrics = checks::train(*algo, envs, 2500, 2500);
  const float plus = algo->act(toy::observation(1.0f), true, rng).values[0];
  const float minus = algo->act(toy::observation(-1.0f), true, rng).values[0];
  INFO("action for s = +1: " << before << " -> " << plus << "; for s = -1: " << minus << " (best +-0.5)");
  CHECK(std::abs(plus - 0.5f) < 0.15f);
  CHECK(std::abs(minus + 0.5f) < 0.15f);
  // The entropy coefficient was tuned down from 1 and every metric is finite.
  CHECK(metrics.back()[2].first == "ent_coef");
  CHECK(metrics.back()[2].second < 0.5);
  for (const auto& [name, value] : metrics.back()) CHECK(std::isfinite(value));
  CHECK(envs.episodes().stats().mean_return > 8.5);  // random actions: about 4.2
}

TEST_CASE("SAC: same seed, same run, checkpoints resume exactly, models round-trip", "[sac][checkpoint]") {
  Setup setup = sac_setup(3);
  setup.sac.learning_starts = 50;
  setup.sac.train_freq = 2;
  setup.sac.gradient_steps = 2;
  checks::same_seed_same_run(setup, checks::sign_envs(2, false), 400);
  checks::resume_is_exact(setup, checks::sign_envs(2, false), 300, 500, 1000);
  VecEnv envs(toy::make_envs(2, false), 3);
  auto algo = make_algorithm(setup, envs.spec());
  checks::train(*algo, envs, 300, 300);
  checks::model_round_trips(setup, *algo, envs.spec(), toy::random_observation);
}

TEST_CASE("SAC needs a bounded Box action space and vector observations", "[sac]") {
  const Setup setup = sac_setup(0);
  CHECK_THROWS_WITH(make_algorithm(setup, toy::SignEnv(true).spec()),
                    Catch::Contains("sign_sac.json") && Catch::Contains("continuous"));
  Spec pixels = toy::SignEnv(false).spec();
  pixels.observation.type = ObsType::UInt8;
  pixels.observation.shape = {4, 4, 3};
  CHECK_THROWS_WITH(make_algorithm(setup, pixels), Catch::Contains("vector observations"));
  Spec unbounded = toy::SignEnv(false).spec();
  unbounded.action.high[0] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_WITH(make_algorithm(setup, unbounded), Catch::Contains("finite action bounds"));
}

TEST_CASE("off-policy actions in [-1, 1] are rescaled to the env's bounds", "[sac]") {
  Spec spec = toy::SignEnv(false).spec();
  spec.action.low = toy::vec({-2.0f, 0.0f});
  spec.action.high = toy::vec({2.0f, 10.0f});
  Setup setup = sac_setup(0);
  setup.sac.buffer_size = 10;
  auto algo = make_algorithm(setup, spec);
  const auto& off = dynamic_cast<const OffPolicy&>(*algo);
  CHECK(off.env_action(toy::vec({-1.0f, -1.0f})).values == toy::vec({-2.0f, 0.0f}));
  CHECK(off.env_action(toy::vec({1.0f, 1.0f})).values == toy::vec({2.0f, 10.0f}));
  CHECK(off.env_action(toy::vec({0.0f, 0.5f})).values.isApprox(toy::vec({0.0f, 7.5f})));
  CHECK(off.env_action(toy::vec({3.0f, -7.0f})).values == toy::vec({2.0f, 0.0f}));  // clipped
}
