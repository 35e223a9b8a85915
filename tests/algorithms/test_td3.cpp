#include <catch2/catch.hpp>

#include "rdsim/algorithms/td3.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "algorithm_checks.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

// The continuous sign task (toy_env.hpp): reward 1 - (a - 0.5 s)^2, best action 0.5 s.
Setup td3_setup(const std::string& algorithm, std::uint64_t seed) {
  Setup c;
  c.algorithm = algorithm;
  c.seed = seed;
  c.source = "sign_td3.json";
  c.network.hidden_sizes = {32, 32};
  c.network.activation = "relu";
  for (Td3Config* t : {&c.td3, static_cast<Td3Config*>(&c.ddpg)}) {
    t->learning_rate = 3e-3;
    t->batch_size = 64;
    t->buffer_size = 5000;
    t->learning_starts = 200;
    t->gamma = 0.5;
  }
  return c;
}

}  // namespace

TEST_CASE("DDPG is TD3 with one critic, no smoothing and no delay", "[td3]") {
  const DdpgConfig ddpg;
  const Td3Config td3;
  CHECK_FALSE(ddpg.twin_q);
  CHECK(ddpg.policy_delay == 1);
  CHECK(ddpg.target_policy_noise == 0.0);
  CHECK(td3.twin_q);
  CHECK(td3.policy_delay == 2);
  CHECK(td3.target_policy_noise == 0.2);
  CHECK(ddpg.learning_rate == td3.learning_rate);
}

TEST_CASE("TD3, DDPG (Gaussian and Ornstein-Uhlenbeck noise) move the policy towards the best action", "[td3]") {
  for (const char* noise : {"normal", "ornstein_uhlenbeck"}) {
    for (const char* algorithm : {"td3", "ddpg"}) {
      Setup setup = td3_setup(algorithm, 2);
      setup.td3.action_noise = setup.ddpg.action_noise = noise;
      setup.td3.action_noise_std = setup.ddpg.action_noise_std = 0.3;
      VecEnv envs(toy::make_envs(2, false), setup.seed);
      auto algo = make_algorithm(setup, envs.spec());
      CHECK(algo->name() == algorithm);
      const auto metrics = checks::train(*algo, envs, 2000, 2000);
      Rng rng(0);
      const float plus = algo->act(toy::observation(1.0f), true, rng).values[0];
      const float minus = algo->act(toy::observation(-1.0f), true, rng).values[0];
      INFO(algorithm << " with " << noise << " noise: action for s = +1: " << plus << ", for s = -1: " << minus);
      CHECK(std::abs(plus - 0.5f) < 0.15f);
      CHECK(std::abs(minus + 0.5f) < 0.15f);
      for (const auto& [name, value] : metrics.back()) CHECK(std::isfinite(value));
    }
  }
}

TEST_CASE("TD3 and DDPG: same seed, same run, checkpoints resume exactly, models round-trip", "[td3][checkpoint]") {
  for (const char* algorithm : {"td3", "ddpg"}) {
    Setup setup = td3_setup(algorithm, 4);
    setup.td3.learning_starts = setup.ddpg.learning_starts = 50;
    setup.td3.action_noise = setup.ddpg.action_noise = "ornstein_uhlenbeck";  // stateful noise is saved too
    checks::same_seed_same_run(setup, checks::sign_envs(2, false), 300);
    checks::resume_is_exact(setup, checks::sign_envs(2, false), 201, 500, 1000);
    VecEnv envs(toy::make_envs(2, false), 4);
    auto algo = make_algorithm(setup, envs.spec());
    checks::train(*algo, envs, 300, 300);
    checks::model_round_trips(setup, *algo, envs.spec(),
                              toy::random_observation);
  }
}

TEST_CASE("TD3 delays actor updates by policy_delay", "[td3]") {
  // With the actor frozen (delay longer than the run), deterministic actions never change.
  Setup setup = td3_setup("td3", 5);
  setup.td3.learning_starts = 20;
  setup.td3.policy_delay = 1'000'000;
  VecEnv envs(toy::make_envs(1, false), 5);
  auto algo = make_algorithm(setup, envs.spec());
  const std::string before = checks::weights(*algo);
  checks::train(*algo, envs, 200, 200);
  CHECK(checks::weights(*algo) == before);
  setup.td3.policy_delay = 3;
  auto moving = make_algorithm(setup, envs.spec());
  checks::train(*moving, envs, 250, 250);
  CHECK(checks::weights(*moving) != before);
}
