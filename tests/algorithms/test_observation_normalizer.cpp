// "normalize_observations" (observation_normalizer.hpp): the transform, its place in every gradient
// algorithm's model file, and exact checkpoints. The CLI-level checks (threads, MPI, resume, errors) are
// tests/app/test_normalize_cli.cpp.
#include <catch2/catch.hpp>

#include <sstream>

#include "algorithm_setup.hpp"
#include "rdsim/algorithms/observation_normalizer.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/parallel/communicator.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "toy_env.hpp"

using Catch::Matchers::Contains;

namespace {

std::unique_ptr<rdsim::Algorithm> normalised(const Setup& s, const rdsim::Spec& spec) {
  rdsim::AlgorithmConfig c = algorithm_config(s);
  c.normalize_observations = true;
  return rdsim::make_algorithm(c, s.seed, spec);
}

bool discrete_algorithm(const std::string& name) { return name == "dqn"; }

}  // namespace

TEST_CASE("observation normaliser: standardises with the statistics of the last refresh, clipped at 10", "[normalize]") {
  rdsim::ObservationNormalizer n(2);
  Eigen::MatrixXf x(2, 3);
  x << 1, 2, 3, 10, 10, 40;
  Eigen::MatrixXf out(2, 3);
  n.apply(x, out);
  CHECK(out == x);  // the identity before any refresh
  n.observe(x);
  n.apply(x, out);
  CHECK(out == x);  // observed, not yet refreshed
  n.refresh(rdsim::single_process_communicator());
  CHECK(n.count() == 3);
  CHECK(n.mean()[0] == Approx(2.0f));
  CHECK(n.mean()[1] == Approx(20.0f));
  n.apply(x, out);
  CHECK(out(0, 0) == Approx(-1.0 / std::sqrt(2.0 / 3.0)).epsilon(1e-5));
  CHECK(out(1, 2) == Approx(20.0 / std::sqrt(200.0)).epsilon(1e-5));
  Eigen::MatrixXf far(2, 1), far_out(2, 1);
  far << 1e6, -1e6;
  n.apply(far, far_out);
  CHECK(far_out(0, 0) == rdsim::ObservationNormalizer::clip);
  CHECK(far_out(1, 0) == -rdsim::ObservationNormalizer::clip);

  std::stringstream bytes;
  n.save(bytes, true);
  rdsim::ObservationNormalizer copy(2);
  copy.load(bytes, true, "test");
  Eigen::MatrixXf again(2, 3);
  copy.apply(x, again);
  CHECK(again == out);
  rdsim::ObservationNormalizer wrong(3);
  std::stringstream same(bytes.str());
  CHECK_THROWS_WITH(wrong.load(same, true, "model.bin"), Contains("model.bin") && Contains("2 inputs"));
}

TEST_CASE("normalize_observations: every gradient algorithm's model file carries the transform, a loaded model acts as trained",
          "[normalize][model]") {
  for (const std::string name : {"ppo", "a2c", "trpo", "dqn", "sac", "td3", "ddpg"}) {
    INFO(name);
    const bool discrete = discrete_algorithm(name);
    rdsim::VecEnv vec(toy::make_envs(2, discrete), 4);
    auto trained = normalised(small_setup(name, 4), vec.spec());
    while (vec.timesteps() < 300) trained->update(vec, {vec.timesteps(), 300});
    std::stringstream model;
    trained->save(model, false);
    auto fresh = normalised(small_setup(name, 77), vec.spec());
    fresh->load(model, false, "test");
    CHECK(model.peek() == std::char_traits<char>::eof());
    rdsim::Rng obs_rng(9), r1(10), r2(10);
    int same = 0;
    for (int k = 0; k < 50; ++k) {
      const rdsim::Observation o = toy::observation(static_cast<float>(obs_rng.uniform(-1, 1)), static_cast<float>(obs_rng.uniform()));
      const rdsim::Action a = trained->act(o, true, r1), b = fresh->act(o, true, r2);
      CHECK(a.index == b.index);
      CHECK(a.values == b.values);
      same += a.index == b.index && a.values == b.values;
    }
    CHECK(same == 50);
    // A model without normalisation cannot read it as its own: the file is longer than its weights.
    auto plain = make_algorithm(small_setup(name, 4), vec.spec());
    std::stringstream again(model.str());
    plain->load(again, false, "test");
    CHECK(again.peek() != std::char_traits<char>::eof());
  }
}

TEST_CASE("normalize_observations: a restored checkpoint continues bit-identically", "[normalize][checkpoint]") {
  for (const std::string name : {"ppo", "sac", "dqn"}) {
    INFO(name);
    const bool discrete = discrete_algorithm(name);
    rdsim::VecEnv vec_a(toy::make_envs(3, discrete), 5);
    auto a = normalised(small_setup(name, 5), vec_a.spec());
    while (vec_a.timesteps() < 150) a->update(vec_a, {vec_a.timesteps(), 2000});
    std::stringstream state;
    a->save(state, true);
    vec_a.save(state);
    rdsim::VecEnv vec_b(toy::make_envs(3, discrete), 123);
    auto b = normalised(small_setup(name, 6), vec_b.spec());
    b->load(state, true, "test");
    REQUIRE(vec_b.load(state, "test"));
    for (int k = 0; k < 5; ++k) CHECK(a->update(vec_a, {vec_a.timesteps(), 2000}) == b->update(vec_b, {vec_b.timesteps(), 2000}));
    std::stringstream wa, wb;
    a->save(wa, false);
    b->save(wb, false);
    CHECK((wa.str() == wb.str()));
  }
}

TEST_CASE("normalize_observations: refused by the algorithms that cannot take it", "[normalize]") {
  rdsim::VecEnv vec(toy::make_envs(1, false), 1);
  CHECK_THROWS_WITH(normalised(small_setup("random", 1), vec.spec()), Contains("cannot normalize observations"));
}
