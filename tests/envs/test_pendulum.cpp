#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "rdsim/core/error.hpp"
#include "rdsim/envs/classic/pendulum.hpp"
#include "rdsim/envs/registry.hpp"

using rdsim::Action;
using rdsim::EnvConfig;
using rdsim::Pendulum;

namespace {

constexpr double pi = std::numbers::pi;

Action torque(float u) { return Action::continuous(Eigen::VectorXf::Constant(1, u)); }

}  // namespace

TEST_CASE("pendulum spec matches Gymnasium Pendulum-v1, the registry publishes its defaults", "[pendulum]") {
  const EnvConfig c = rdsim::default_env_config("pendulum");
  CHECK(c.max_steps == 200);
  CHECK_FALSE(c.is_discrete);
  auto env = rdsim::make_env(c);
  const auto& spec = env->spec();
  CHECK(spec.env_name == "pendulum");
  CHECK(spec.observation.shape == std::vector<int>{3});
  CHECK(spec.observation.high == (Eigen::VectorXf(3) << 1.0f, 1.0f, 8.0f).finished());
  CHECK(spec.observation.low == (Eigen::VectorXf(3) << -1.0f, -1.0f, -8.0f).finished());
  CHECK_FALSE(spec.action.discrete);
  CHECK(spec.action.dim() == 1);
  CHECK(spec.action.low[0] == -2.0f);
  CHECK(spec.action.high[0] == 2.0f);
  CHECK(spec.max_episode_steps == 200);
  CHECK(spec.control_dt == Approx(0.05));

  EnvConfig discrete = c;
  discrete.is_discrete = true;
  CHECK_THROWS_WITH(rdsim::make_env(discrete), Catch::Contains("is_discrete"));
}

TEST_CASE("pendulum steps by Gymnasium's equations, reward from the state before the step", "[pendulum]") {
  Pendulum env(rdsim::default_env_config("pendulum"));
  env.reset(1);
  // Horizontal (theta = pi/2), at rest, full torque: theta_dot' = (15 sin(pi/2) + 3 * 2) 0.05 = 1.05.
  env.set_state(pi / 2, 0.0);
  auto r = env.step(torque(2.0f));
  CHECK(r.reward == Approx(-(pi * pi / 4 + 0.001 * 4)));
  const double theta = pi / 2 + 1.05 * 0.05;
  CHECK(r.observation.values[0] == Approx(std::cos(theta)));
  CHECK(r.observation.values[1] == Approx(std::sin(theta)));
  CHECK(r.observation.values[2] == Approx(1.05));
  CHECK_FALSE(r.terminated);
  CHECK_FALSE(r.truncated);

  // Torque beyond 2 is clipped; speed is clipped to 8 rad/s.
  env.set_state(pi / 2, 7.9);
  r = env.step(torque(50.0f));
  CHECK(r.observation.values[2] == Approx(8.0));
  CHECK(r.reward == Approx(-(pi * pi / 4 + 0.1 * 7.9 * 7.9 + 0.001 * 4)));

  // The angle cost uses the angle normalised to [-pi, pi): 3 pi / 2 costs like -pi / 2.
  env.set_state(3 * pi / 2, 0.0);
  r = env.step(torque(0.0f));
  CHECK(r.reward == Approx(-(pi * pi / 4)));
  CHECK(Pendulum::normalize_angle(3 * pi / 2) == Approx(-pi / 2));
  CHECK(Pendulum::normalize_angle(-3 * pi / 2) == Approx(pi / 2));
  CHECK(Pendulum::normalize_angle(pi) == Approx(-pi));
  CHECK(Pendulum::normalize_angle(0.25) == Approx(0.25));

  // Upright and still is the best state: reward 0 and it stays there.
  env.set_state(0.0, 0.0);
  r = env.step(torque(0.0f));
  CHECK(r.reward == 0.0f);
  CHECK(r.observation.values[0] == 1.0f);
  CHECK_THROWS_AS(env.step(Action::continuous(Eigen::VectorXf::Zero(2))), rdsim::Error);
}

TEST_CASE("pendulum resets uniformly in (-pi, pi) x (-1, 1), never terminates, truncates at 200 steps", "[pendulum]") {
  Pendulum env(rdsim::default_env_config("pendulum"));
  double max_speed = 0.0, min_cos = 1.0;
  for (int k = 0; k < 300; ++k) {
    const auto o = k == 0 ? env.reset(5).values : env.reset().values;
    CHECK(std::abs(o[0] * o[0] + o[1] * o[1] - 1.0f) < 1e-5f);
    CHECK(std::abs(o[2]) <= 1.0f);
    max_speed = std::max(max_speed, static_cast<double>(std::abs(o[2])));
    min_cos = std::min(min_cos, static_cast<double>(o[0]));
  }
  CHECK(max_speed > 0.9);
  CHECK(min_cos < -0.95);  // angles near +-pi occur
  env.reset(3);
  int steps = 0;
  for (bool done = false; !done; ++steps) {
    const auto r = env.step(torque(1.0f));
    CHECK_FALSE(r.terminated);
    CHECK(r.reward <= 0.0f);
    CHECK(r.reward >= -16.2736f);  // pi^2 + 0.1 * 64 + 0.001 * 4
    done = r.truncated;
  }
  CHECK(steps == 200);
}

TEST_CASE("pendulum state round-trips: a restored env continues identically", "[pendulum]") {
  Pendulum a(rdsim::default_env_config("pendulum")), b(rdsim::default_env_config("pendulum"));
  a.reset(9);
  for (int k = 0; k < 30; ++k) a.step(torque(0.7f));
  b.load_state(a.save_state(), "state");
  for (int k = 0; k < 250; ++k) {
    const auto ra = a.step(torque(-1.3f)), rb = b.step(torque(-1.3f));
    CHECK(ra.observation.values == rb.observation.values);
    CHECK(ra.reward == rb.reward);
    CHECK(ra.truncated == rb.truncated);
    if (ra.truncated) CHECK(a.reset().values == b.reset().values);
  }
  CHECK_THROWS_AS(b.load_state("short", "state"), rdsim::Error);
}
