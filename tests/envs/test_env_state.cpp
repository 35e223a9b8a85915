// EnvState (core/env_state.hpp) for every registered env: an env restored from a saved state
// continues bit for bit like the env it was saved from, whatever the restored env did before.
#include <catch2/catch.hpp>

#include <cstring>
#include <memory>

#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "env_test_util.hpp"

using namespace rdsim;

namespace {

Action random_action(const Spec& spec, Rng& rng) {
  if (spec.action.discrete) return Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(spec.action.n))));
  Eigen::VectorXf v(spec.action.dim());
  for (int i = 0; i < v.size(); ++i) v[i] = static_cast<float>(rng.uniform(-1.0, 1.0));
  return Action::continuous(v);
}

bool same_bits(const Eigen::VectorXf& a, const Eigen::VectorXf& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), static_cast<size_t>(a.size()) * sizeof(float)) == 0;
}

// Steps `env` with actions from `rng`, resetting when an episode ends (as VecEnv does).
void run(Env& env, Rng& rng, int steps) {
  for (int i = 0; i < steps; ++i) {
    const StepResult r = env.step(random_action(env.spec(), rng));
    if (r.terminated || r.truncated) env.reset();
  }
}

EnvConfig config_of(const std::string& name) {
  EnvConfig c = default_env_config(name);
  if (auto* reach = c.find<ReachOptions>()) reach->random_target = true;
  return c;
}

}  // namespace

namespace {

// a runs 137 steps, b 61 steps of its own; b loads a's state; then both must step bit for bit alike.
void check_restore(const EnvConfig& config) {
  auto a = make_env(config), b = make_env(config);
  auto* sa = dynamic_cast<EnvState*>(a.get());
  auto* sb = dynamic_cast<EnvState*>(b.get());
  REQUIRE(sa);
  REQUIRE(sb);
  Rng actions_a(1), actions_b(2);
  a->reset(7);
  run(*a, actions_a, 137);
  b->reset(99);
  run(*b, actions_b, 61);  // b has its own history (and engine caches) before the restore
  sa->drop_caches();
  const std::string saved = sa->save_state();
  sb->load_state(saved, "test");
  CHECK(sb->save_state() == saved);

  Rng ra(5), rb(5);
  int episodes_ended = 0;
  for (int i = 0; i < 600; ++i) {
    const StepResult x = a->step(random_action(a->spec(), ra));
    const StepResult y = b->step(random_action(b->spec(), rb));
    INFO("step " << i);
    REQUIRE(same_bits(x.observation.values, y.observation.values));
    REQUIRE(x.observation.pixels == y.observation.pixels);
    REQUIRE(std::memcmp(&x.reward, &y.reward, sizeof(float)) == 0);
    REQUIRE(x.terminated == y.terminated);
    REQUIRE(x.truncated == y.truncated);
    REQUIRE(x.info.collision == y.info.collision);
    REQUIRE(x.info.success == y.info.success);
    if (x.terminated || x.truncated) {
      ++episodes_ended;
      REQUIRE(same_bits(a->reset().values, b->reset().values));
    }
  }
  CHECK(episodes_ended > 0);  // resets are covered too
  CHECK(sa->save_state() == sb->save_state());
}

}  // namespace

TEST_CASE("every env saves and restores its full state: the restored env continues bit for bit", "[env_state]") {
  for (const EnvEntry& entry : env_registry()) {
    INFO(entry.name);
    check_restore(config_of(entry.name));
  }
}

TEST_CASE("the paper presets restore bit for bit too: joint-row warm starts are engine caches", "[env_state]") {
  // Position motors with warm-started joint rows, the InMoov's welds freed and made again.
  for (const char* name : {"jaka_button", "inmoov_tomato"}) {
    INFO(name);
    EnvConfig config = test::paper_env_config(name);
    config.max_steps = 200;  // episodes end within the run
    check_restore(config);
  }
}

TEST_CASE("env states of another env, truncated or damaged are rejected by name", "[env_state]") {
  auto jaka = make_env(config_of("jaka_button"));
  auto inmoov = make_env(config_of("inmoov_tomato"));
  auto cartpole = make_env(config_of("cartpole"));
  jaka->reset(1);
  inmoov->reset(1);
  cartpole->reset(1);
  const std::string state = dynamic_cast<EnvState&>(*jaka).save_state();
  auto& target = dynamic_cast<EnvState&>(*inmoov);
  CHECK_THROWS_WITH(target.load_state(state, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("jaka_button"));
  CHECK_THROWS_WITH(dynamic_cast<EnvState&>(*cartpole).load_state(state, "ckpt.bin"), Catch::Contains("ckpt.bin"));
  auto& self = dynamic_cast<EnvState&>(*jaka);
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, state.size() / 2, state.size() - 1}) {
    INFO("cut at " << cut);
    CHECK_THROWS_AS(self.load_state(state.substr(0, cut), "ckpt.bin"), Error);
  }
  CHECK_THROWS_WITH(self.load_state(state + "x", "ckpt.bin"), Catch::Contains("trailing"));
  // A NaN joint position (the last float of the state before target/ee/time is the last target).
  std::string nan_state = state;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan_state.data() + nan_state.size() - 8 - 24 - 4, &nan, 4);
  CHECK_THROWS_WITH(self.load_state(nan_state, "ckpt.bin"), Catch::Contains("not finite"));
}
