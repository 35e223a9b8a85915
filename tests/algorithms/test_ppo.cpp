#include <catch2/catch.hpp>
#include <sstream>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/algorithms/on_policy.hpp"
#include "rdsim/algorithms/rollout.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_setup.hpp"
#include "toy_env.hpp"

namespace {

Setup ppo_config(std::uint64_t seed = 1) {
  Setup c;
  c.algorithm = "ppo";
  c.seed = seed;
  c.network.hidden_sizes = {32, 32};
  c.ppo.n_steps = 32;
  c.ppo.batch_size = 64;
  c.ppo.n_epochs = 4;
  c.ppo.learning_rate = 3e-3;
  return c;
}

double train(rdsim::Algorithm& algo, rdsim::VecEnv& vec, long long steps) {
  while (vec.timesteps() < steps) algo.update(vec, {vec.timesteps(), steps});
  return vec.episodes().stats().mean_return;
}

}  // namespace

TEST_CASE("rollouts bootstrap truncated episodes from V(final observation), never terminated ones", "[rollout]") {
  std::vector<std::unique_ptr<rdsim::Env>> envs;
  envs.push_back(std::make_unique<toy::SignEnv>(true, 3, 0));   // truncated after 3 steps
  envs.push_back(std::make_unique<toy::SignEnv>(true, 10, 2));  // terminated at step 2
  rdsim::VecEnv vec(std::move(envs), 3);
  rdsim::NetworkConfig net;
  rdsim::Rng init(1), rng(2);
  rdsim::ActorCritic policy(vec.spec(), net, init);
  rdsim::RolloutBuffer r;
  r.resize(4, 2, 2, 1);
  rdsim::collect_rollout(vec, policy, rng, r);

  using rdsim::EpisodeEnd;
  const std::vector<EpisodeEnd> expected = {EpisodeEnd::None, EpisodeEnd::None,       // t = 0
                                            EpisodeEnd::None, EpisodeEnd::Terminated, // t = 1
                                            EpisodeEnd::Truncated, EpisodeEnd::None,  // t = 2
                                            EpisodeEnd::None, EpisodeEnd::Terminated};// t = 3
  CHECK(r.ends == expected);
  // The truncated episode's final observation is (s, 3/3) for s = +-1.
  Eigen::MatrixXf finals(2, 2);
  finals << -1, 1, 1, 1;
  const Eigen::VectorXf v = policy.predict_values(finals);
  CHECK((r.final_values[4] == Approx(v[0]) || r.final_values[4] == Approx(v[1])));
  CHECK(r.final_values[4] != 0.0f);
  for (int i : {0, 1, 2, 3, 5, 6, 7}) CHECK(r.final_values[i] == 0.0f);
  CHECK(r.last_values.isApprox(policy.predict_values(vec.observations().values)));
  for (int i = 0; i < 8; ++i) CHECK(r.observations(1, i) < 1.0f);  // acting never sees a final observation
  CHECK(r.rewards.minCoeff() >= 0.0f);
}

TEST_CASE("PPO learns a discrete toy task", "[ppo]") {
  rdsim::VecEnv vec(toy::make_envs(4), 1);
  auto algo = make_algorithm(ppo_config(), vec.spec());
  CHECK(algo->name() == "ppo");
  const double mean_return = train(*algo, vec, 6000);
  INFO("mean return " << mean_return << " (random: 5, best: 10)");
  CHECK(mean_return > 9.0);
}

TEST_CASE("PPO learns a continuous toy task", "[ppo]") {
  rdsim::VecEnv vec(toy::make_envs(4, false), 1);
  auto config = ppo_config();
  config.ppo.learning_rate = 1e-2;
  auto algo = make_algorithm(config, vec.spec());
  train(*algo, vec, 1000);
  const double early = vec.episodes().stats().mean_return;
  const double late = train(*algo, vec, 12000);
  INFO("mean return early " << early << ", late " << late << " (best: 10)");
  CHECK(late > 8.5);
  CHECK(late > early + 2.0);
}

TEST_CASE("a saved model loads into a fresh algorithm and acts identically", "[ppo][model]") {
  for (bool discrete : {true, false}) {
    rdsim::VecEnv vec(toy::make_envs(2, discrete), 4);
    auto trained = make_algorithm(ppo_config(4), vec.spec());
    train(*trained, vec, 200);
    std::stringstream weights;
    trained->save(weights, false);
    auto fresh = make_algorithm(ppo_config(77), vec.spec());
    fresh->load(weights, false, "test");
    rdsim::Rng obs_rng(9), r1(10), r2(10);
    for (int k = 0; k < 50; ++k) {
      rdsim::Observation o;
      o.values.resize(2);
      o.values << static_cast<float>(obs_rng.uniform(-1, 1)), static_cast<float>(obs_rng.uniform());
      const auto a = trained->act(o, true, r1), b = fresh->act(o, true, r2);
      CHECK(a.index == b.index);
      CHECK(a.values == b.values);
      const auto sa = trained->act(o, false, r1), sb = fresh->act(o, false, r2);
      CHECK(sa.index == sb.index);
      CHECK(sa.values == sb.values);
    }
    auto other_shape = ppo_config();
    other_shape.network.hidden_sizes = {16};
    auto wrong = make_algorithm(other_shape, vec.spec());
    std::stringstream again;
    trained->save(again, false);
    CHECK_THROWS_AS(wrong->load(again, false, "test"), rdsim::Error);
  }
}

TEST_CASE("PPO training state round-trips: a restored run continues bit-identically", "[ppo][checkpoint]") {
  const auto config = ppo_config(5);
  rdsim::VecEnv vec_a(toy::make_envs(3), 5);
  auto a = make_algorithm(config, vec_a.spec());
  for (int k = 0; k < 3; ++k) a->update(vec_a, {vec_a.timesteps(), 2000});
  std::stringstream state;
  a->save(state, true);
  vec_a.save(state);

  rdsim::VecEnv vec_b(toy::make_envs(3), 123);
  auto b = make_algorithm(ppo_config(6), vec_b.spec());
  b->load(state, true, "test");
  REQUIRE(vec_b.load(state, "test"));
  for (int k = 0; k < 2; ++k) {
    const auto ma = a->update(vec_a, {vec_a.timesteps(), 2000});
    const auto mb = b->update(vec_b, {vec_b.timesteps(), 2000});
    CHECK(ma == mb);
  }
  std::stringstream wa, wb;  // weights (the Rng bytes of a full state may differ in padding only)
  a->save(wa, false);
  b->save(wb, false);
  CHECK((wa.str() == wb.str()));
}

TEST_CASE("PPO metrics are reported in a fixed order and stay finite", "[ppo]") {
  rdsim::VecEnv vec(toy::make_envs(2), 2);
  auto config = ppo_config();
  config.ppo.clip_range_vf = 0.2;
  config.ppo.ent_coef = 0.01;
  config.ppo.anneal_lr = true;
  auto algo = make_algorithm(config, vec.spec());
  const auto m1 = algo->update(vec, {0, 640});
  const auto m2 = algo->update(vec, {vec.timesteps(), 640});
  REQUIRE(m1.size() == m2.size());
  for (std::size_t i = 0; i < m1.size(); ++i) {
    CHECK(m1[i].first == m2[i].first);
    CHECK(std::isfinite(m2[i].second));
  }
  auto lr = [](const rdsim::Metrics& m) {
    for (const auto& [k, v] : m) if (k == "learning_rate") return v;
    return -1.0;
  };
  CHECK(lr(m1) == Approx(3e-3 * (1.0 - 64.0 / 640.0)));
  CHECK(lr(m2) < lr(m1));
}
