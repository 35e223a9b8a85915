#include <catch2/catch.hpp>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "algorithm_setup.hpp"
#include "toy_env.hpp"

TEST_CASE("A2C learns a discrete toy task (RMSprop and Adam)", "[a2c]") {
  for (const char* optimizer : {"rmsprop", "adam"}) {
    Setup c;
    c.algorithm = "a2c";
    c.seed = 3;
    c.network.hidden_sizes = {32, 32};
    c.a2c.optimizer = optimizer;
    c.a2c.learning_rate = 3e-3;
    rdsim::VecEnv vec(toy::make_envs(8), 3);
    auto algo = make_algorithm(c, vec.spec());
    CHECK(algo->name() == "a2c");
    while (vec.timesteps() < 8000) algo->update(vec, {vec.timesteps(), 8000});
    INFO(optimizer << ": mean return " << vec.episodes().stats().mean_return << " (random: 5, best: 10)");
    CHECK(vec.episodes().stats().mean_return > 9.0);
  }
}

TEST_CASE("A2C with a shared trunk learns too", "[a2c]") {
  Setup c;
  c.algorithm = "a2c";
  c.network.hidden_sizes = {32, 32};
  c.network.shared = true;
  c.a2c.learning_rate = 3e-3;
  // The toy task's values (up to 10, driven by the time feature) would otherwise claim the whole
  // shared trunk; a small value weight leaves it room for the sign the policy needs.
  c.a2c.vf_coef = 0.01;
  rdsim::VecEnv vec(toy::make_envs(8), 4);
  auto algo = make_algorithm(c, vec.spec());
  while (vec.timesteps() < 8000) algo->update(vec, {vec.timesteps(), 8000});
  INFO("mean return " << vec.episodes().stats().mean_return);
  CHECK(vec.episodes().stats().mean_return > 9.0);
}
