#pragma once
// Checks every algorithm passes, whatever it learns: the same seed gives the same run, a
// checkpoint resumes bit-identically, and a model file alone acts like the trained algorithm.
#include <catch2/catch.hpp>

#include <functional>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_setup.hpp"
#include "toy_env.hpp"

namespace checks {

using EnvFactory = std::function<std::vector<std::unique_ptr<rdsim::Env>>()>;

// `n` toy sign envs (toy_env.hpp).
inline EnvFactory sign_envs(int n, bool discrete) {
  return [n, discrete] { return toy::make_envs(n, discrete); };
}

inline std::vector<rdsim::Metrics> train(rdsim::Algorithm& algo, rdsim::VecEnv& envs, long long until, long long total) {
  std::vector<rdsim::Metrics> all;
  while (envs.timesteps() < until) all.push_back(algo.update(envs, {envs.timesteps(), total}));
  return all;
}

inline std::string weights(const rdsim::Algorithm& algo) {
  std::ostringstream out;
  algo.save(out, false);
  return out.str();
}

// Two runs with one seed give identical metrics, episodes and weights.
inline void same_seed_same_run(const Setup& setup, const EnvFactory& make_envs, long long steps) {
  rdsim::VecEnv a(make_envs(), setup.seed), b(make_envs(), setup.seed);
  auto algo_a = make_algorithm(setup, a.spec()), algo_b = make_algorithm(setup, b.spec());
  CHECK(train(*algo_a, a, steps, steps) == train(*algo_b, b, steps, steps));
  const auto ea = a.episodes().take_finished(), eb = b.episodes().take_finished();
  REQUIRE(ea.size() == eb.size());
  for (std::size_t i = 0; i < ea.size(); ++i) CHECK(ea[i].episode_return == eb[i].episode_return);
  CHECK(weights(*algo_a) == weights(*algo_b));
}

// After `before` steps the training state is saved with the envs'; a fresh algorithm of another
// seed loads it and continues to `after` exactly like the original.
inline void resume_is_exact(const Setup& setup, const EnvFactory& make_envs, long long before, long long after,
                            long long total) {
  rdsim::VecEnv envs(make_envs(), setup.seed);
  auto algo = make_algorithm(setup, envs.spec());
  train(*algo, envs, before, total);
  std::stringstream state;
  algo->save(state, true);
  envs.save(state);
  const std::vector<rdsim::Metrics> straight = train(*algo, envs, after, total);

  Setup other = setup;
  other.seed = setup.seed + 1000;
  rdsim::VecEnv envs2(make_envs(), other.seed);
  auto resumed = make_algorithm(other, envs2.spec());
  resumed->load(state, true, "checkpoint.bin");
  REQUIRE(envs2.load(state, "checkpoint.bin"));
  CHECK(state.peek() == std::char_traits<char>::eof());  // everything saved was read back
  CHECK(train(*resumed, envs2, after, total) == straight);
  CHECK(weights(*resumed) == weights(*algo));
}

// The model alone (another seed's fresh algorithm loading it) acts like the trained one, in
// deterministic and sampled acting; a truncated model is a clear error.
inline void model_round_trips(const Setup& setup, rdsim::Algorithm& trained, const rdsim::Spec& spec,
                              const std::function<rdsim::Observation(rdsim::Rng&)>& observation) {
  std::stringstream model;
  trained.save(model, false);
  Setup other = setup;
  other.seed = setup.seed + 77;
  auto fresh = make_algorithm(other, spec);
  fresh->load(model, false, "model.bin");
  rdsim::Rng obs_rng(9), r1(10), r2(10);
  for (int k = 0; k < 30; ++k) {
    const rdsim::Observation o = observation(obs_rng);
    for (bool deterministic : {true, false}) {
      const rdsim::Action a = trained.act(o, deterministic, r1), b = fresh->act(o, deterministic, r2);
      CHECK(a.index == b.index);
      CHECK(a.values == b.values);
    }
  }
  const std::string bytes = weights(trained);
  std::stringstream truncated(bytes.substr(0, bytes.size() / 2));
  CHECK_THROWS_AS(fresh->load(truncated, false, "model.bin"), rdsim::Error);
}

}  // namespace checks
