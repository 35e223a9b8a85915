// Domain randomization ("randomize" in a robot env's config, envs/randomization.hpp): action latency
// runs each action that many steps late, observation noise has the configured spread and spares the
// desired goal, both follow the reset seed and survive save/load; bad values are one clear error.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "../error_of.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/registry.hpp"

using Catch::Matchers::Contains;
using rdsim::test::error_of;

namespace {

std::unique_ptr<rdsim::Env> make(const nlohmann::json& env) {
  rdsim::ConfigReader r(env, "x.json", "env");
  return rdsim::make_env(rdsim::read_env_config(r));
}

std::vector<rdsim::Action> random_actions(const rdsim::Spec& spec, int n, std::uint64_t seed) {
  rdsim::Rng rng(seed);
  std::vector<rdsim::Action> actions;
  for (int i = 0; i < n; ++i) {
    if (spec.action.discrete) {
      actions.push_back(rdsim::Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(spec.action.n)))));
    } else {
      Eigen::VectorXf v(spec.action.dim());
      for (int k = 0; k < v.size(); ++k) v[k] = static_cast<float>(rng.uniform(-1.0, 1.0));
      actions.push_back(rdsim::Action::continuous(v));
    }
  }
  return actions;
}

}  // namespace

TEST_CASE("randomize: action latency runs each action that many steps late, the first ones the episode's first",
          "[randomize]") {
  for (const char* name : {"jaka_button", "push"}) {
    INFO(name);
    auto late = make({{"name", name}, {"randomize", {{"action_latency", 2}}}});
    auto plain = make({{"name", name}});
    const auto actions = random_actions(plain->spec(), 40, 7);
    rdsim::Observation a = late->reset(3), b = plain->reset(3);
    CHECK(a.values == b.values);
    for (int t = 0; t < 40; ++t) {
      const rdsim::StepResult s = late->step(actions[static_cast<std::size_t>(t)]);
      const rdsim::StepResult p = plain->step(actions[static_cast<std::size_t>(std::max(t - 2, 0))]);
      INFO("step " << t);
      REQUIRE(s.observation.values == p.observation.values);
      CHECK(s.reward == p.reward);
      if (s.terminated || s.truncated) break;
    }
    // A new episode starts with nothing pending: its first action runs at once again.
    a = late->reset(4);
    b = plain->reset(4);
    CHECK(late->step(actions[5]).observation.values == plain->step(actions[5]).observation.values);
  }
}

TEST_CASE("randomize: observation noise has the configured spread, spares the desired goal and follows the seed",
          "[randomize]") {
  auto noisy = make({{"name", "reach_goal"}, {"randomize", {{"observation_noise", 0.01}}}});
  auto plain = make({{"name", "reach_goal"}});
  const rdsim::GoalLayout& goal = plain->spec().goal;
  REQUIRE(goal.active());
  const auto actions = random_actions(plain->spec(), 200, 8);
  double sum = 0.0, squares = 0.0;
  int n = 0;
  std::vector<float> first_run;
  for (int run = 0; run < 2; ++run) {
    rdsim::Observation a = noisy->reset(11), b = plain->reset(11);
    for (std::size_t t = 0; t < actions.size(); ++t) {
      for (int i = 0; i < a.values.size(); ++i) {
        const double d = a.values[i] - b.values[i];
        if (i >= goal.desired_offset()) {
          CHECK(d == 0.0);
        } else if (run == 0) {
          sum += d;
          squares += d * d;
          ++n;
        }
        if (run == 0) first_run.push_back(a.values[i]);
        else CHECK(a.values[i] == first_run[static_cast<std::size_t>(t * static_cast<std::size_t>(a.values.size()) + static_cast<std::size_t>(i))]);
      }
      const rdsim::StepResult s = noisy->step(actions[t]), p = plain->step(actions[t]);
      CHECK(s.reward == p.reward);  // the noise is in what is observed, not in the state
      if (s.terminated || s.truncated) {
        a = noisy->reset();
        b = plain->reset();
      } else {
        a = s.observation;
        b = p.observation;
      }
    }
  }
  const double mean = sum / n, sd = std::sqrt(squares / n - mean * mean);
  INFO(n << " noisy values: mean " << mean << ", sd " << sd);
  CHECK(std::abs(mean) < 0.001);
  CHECK(sd == Approx(0.01).epsilon(0.05));
  // Another seed, other noise.
  CHECK(noisy->reset(12).values != noisy->reset(11).values);
}

TEST_CASE("randomize: a saved state continues the pending actions and the noise exactly", "[randomize]") {
  const nlohmann::json config = {{"name", "jaka_button"},
                                 {"randomize", {{"action_latency", 3}, {"observation_noise", 0.005}}}};
  auto a = make(config), b = make(config);
  const auto actions = random_actions(a->spec(), 30, 9);
  a->reset(5);
  for (int t = 0; t < 10; ++t) a->step(actions[static_cast<std::size_t>(t)]);
  auto* state = dynamic_cast<rdsim::EnvState*>(a.get());
  REQUIRE(state);
  const std::string saved = state->save_state();
  b->reset(99);
  dynamic_cast<rdsim::EnvState&>(*b).load_state(saved, "checkpoint.bin");
  for (int t = 10; t < 30; ++t) {
    const auto sa = a->step(actions[static_cast<std::size_t>(t)]), sb = b->step(actions[static_cast<std::size_t>(t)]);
    CHECK(sa.observation.values == sb.observation.values);
    CHECK(sa.reward == sb.reward);
  }
  std::string damaged = saved;
  damaged.resize(damaged.size() - 2);
  CHECK_THROWS_WITH(dynamic_cast<rdsim::EnvState&>(*b).load_state(damaged, "checkpoint.bin"), Contains("checkpoint.bin"));
}

TEST_CASE("randomize: bad values are one clear error", "[randomize][config]") {
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", {{"observation_noise", -0.1}}}}); }),
             Contains("env.randomize.observation_noise"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", {{"action_latency", -1}}}}); }),
             Contains("env.randomize.action_latency"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"max_steps", 50}, {"randomize", {{"action_latency", 50}}}}); }),
             Contains("env.randomize.action_latency: 50 steps is not shorter than jaka_button's episode (max_steps 50)"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", {{"mass", 0.3}}}}); }),
             Contains("env.randomize.mass"));
  CHECK_THAT(error_of([] { make({{"name", "jaka_button"}, {"randomize", 3}}); }), Contains("env.randomize"));
  CHECK_THAT(error_of([] {
               make({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"randomize", {{"observation_noise", 0.01}}}});
             }),
             Contains("env.randomize.observation_noise") && Contains("ground_truth"));
  CHECK_THAT(error_of([] { make({{"name", "cartpole"}, {"randomize", {{"action_latency", 1}}}}); }),
             Contains("env.randomize"));
  // Latency alone works on pixels.
  CHECK_NOTHROW(make({{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"randomize", {{"action_latency", 1}}}}));
}
