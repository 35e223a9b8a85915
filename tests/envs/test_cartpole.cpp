#include <array>
#include <catch2/catch.hpp>
#include <cmath>

#include "env_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/classic/cartpole.hpp"
#include "rdsim/envs/registry.hpp"

using rdsim::Action;
using rdsim::CartPole;
using rdsim::EnvConfig;

namespace {

EnvConfig cartpole_config() { return rdsim::test::env_config("cartpole"); }

// Gym CartPole-v1's equations, written out independently of the env, in double.
std::array<double, 4> reference_step(std::array<double, 4> s, int action) {
  const double g = 9.8, mc = 1.0, mp = 0.1, l = 0.5, tau = 0.02;
  const double f = action == 1 ? 10.0 : -10.0;
  const double total = mc + mp;
  const double temp = (f + mp * l * s[3] * s[3] * std::sin(s[2])) / total;
  const double th_acc = (g * std::sin(s[2]) - std::cos(s[2]) * temp) /
                        (l * (4.0 / 3.0 - mp * std::cos(s[2]) * std::cos(s[2]) / total));
  const double x_acc = temp - mp * l * th_acc * std::cos(s[2]) / total;
  return {s[0] + tau * s[1], s[1] + tau * x_acc, s[2] + tau * s[3], s[3] + tau * th_acc};
}

}  // namespace

// Spaces, limits, determinism and truncation: tests/envs/test_env_contract.cpp.
TEST_CASE("cartpole observation bounds are Gym CartPole-v1's", "[cartpole]") {
  auto env = rdsim::make_env(cartpole_config());
  const auto& spec = env->spec();
  CHECK(spec.observation.high[0] == Approx(4.8f));
  CHECK(spec.observation.high[2] == Approx(2 * 12 * 2 * M_PI / 360));
}

TEST_CASE("cartpole reset draws each state variable from U(-0.05, 0.05), reproducibly", "[cartpole]") {
  CartPole a(cartpole_config()), b(cartpole_config());
  const auto first = a.reset(42).values;
  CHECK(b.reset(42).values == first);
  bool differs = false;
  for (int k = 0; k < 200; ++k) {
    const auto o = a.reset().values;  // the stream continues without a seed
    REQUIRE(o.size() == 4);
    CHECK(o.cwiseAbs().maxCoeff() <= 0.05f);
    differs = differs || o != first;
  }
  CHECK(differs);
  CHECK(a.reset(7).values != b.reset(8).values);
}

TEST_CASE("cartpole steps follow the Euler-integrated Gym equations", "[cartpole]") {
  CartPole env(cartpole_config());
  const auto o = env.reset(3).values;
  std::array<double, 4> s{o[0], o[1], o[2], o[3]};
  for (int t = 0; t < 20; ++t) {
    const int a = (t * 7 / 3) % 2;
    s = reference_step(s, a);
    const auto r = env.step(Action::discrete(a));
    CHECK(r.reward == 1.0f);
    for (int i = 0; i < 4; ++i) CHECK(r.observation.values[i] == Approx(s[static_cast<std::size_t>(i)]).margin(1e-5));
  }
  // Pushing right accelerates the cart right and tips the pole left (negative angular rate).
  const auto before = env.reset(5).values;
  const auto after = env.step(Action::discrete(1)).observation.values;
  CHECK(after[1] > before[1]);
  CHECK(after[3] < before[3]);
}

TEST_CASE("cartpole terminates past the angle/position limits, surviving to the step limit is success", "[cartpole]") {
  CartPole env(cartpole_config());
  env.reset(1);
  rdsim::StepResult r;
  int steps = 0;
  do {
    r = env.step(Action::discrete(1));
    ++steps;
  } while (!r.terminated && !r.truncated);
  CHECK(r.terminated);
  CHECK_FALSE(r.info.success);
  CHECK(steps < 100);
  CHECK(r.reward == 1.0f);  // Gym rewards the failing step too
  const auto& v = r.observation.values;
  CHECK((std::abs(v[0]) > 2.4f || std::abs(v[2]) > 12.0f * M_PI / 180.0f));

  EnvConfig short_episodes = cartpole_config();
  short_episodes.max_steps = 10;
  CartPole limited(short_episodes);
  limited.reset(1);
  for (int t = 1; t <= 10; ++t) r = limited.step(Action::discrete(t % 2));
  REQUIRE(r.truncated);
  CHECK(r.info.success);
}

TEST_CASE("cartpole state save/load continues bit-identically", "[cartpole]") {
  CartPole env(cartpole_config());
  env.reset(11);
  for (int t = 0; t < 5; ++t) env.step(Action::discrete(t % 2));
  const std::string state = env.save_state();
  std::vector<Eigen::VectorXf> first;
  for (int t = 0; t < 8; ++t) first.push_back(env.step(Action::discrete(1 - t % 2)).observation.values);
  first.push_back(env.reset().values);

  CartPole other(cartpole_config());
  other.reset(999);
  other.load_state(state, "test");
  for (int t = 0; t < 8; ++t) CHECK(other.step(Action::discrete(1 - t % 2)).observation.values == first[static_cast<std::size_t>(t)]);
  CHECK(other.reset().values == first.back());
  CHECK_THROWS_AS(other.load_state("short", "test"), rdsim::Error);
}

TEST_CASE("cartpole rejects options it does not have", "[cartpole]") {
  EnvConfig pixels = cartpole_config();
  pixels.observation = rdsim::ObservationMode::RawPixels;
  CHECK_THROWS_AS(CartPole(pixels), rdsim::Error);
  EnvConfig box = cartpole_config();
  box.is_discrete = false;
  CHECK_THROWS_AS(CartPole(box), rdsim::Error);
}
