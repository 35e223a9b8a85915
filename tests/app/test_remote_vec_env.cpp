// Remote envs in a VecEnv: every env's step request is in flight at once (Env::begin_step), with
// the same results as local envs, and a failed step leaves every link ready for the next one.
#include <catch2/catch.hpp>

#include "../remote/remote_test_util.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/remote_env.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;

namespace {

// A CurveZMQ server on a free loopback port that admits one client key, for one test.
struct Served {
  test::Scratch dir;
  test::TestKeys keys{dir};
  test::ServerThread server{test::curve_options(keys)};
  explicit Served(const std::string& tag) : dir(tag) {}
  RemoteEnvConfig link() const { return keys.link(server.endpoint()); }
};

EnvConfig short_jaka() {
  EnvConfig config = default_env_config("jaka_button");
  config.get<ReachOptions>().random_target = true;
  config.max_steps = 25;  // several resets within the test
  return config;
}

std::vector<std::unique_ptr<Env>> local_envs(const EnvConfig& config, int n) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(make_env(config));
  return envs;
}

std::vector<std::unique_ptr<Env>> remote_envs(const RemoteEnvConfig& link, const EnvConfig& config, int n) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(connect_remote_env(link, config));
  return envs;
}

std::vector<Action> actions_at(int t, int n) {
  std::vector<Action> a;
  for (int i = 0; i < n; ++i) a.push_back(Action::discrete((t + 2 * i) % 6));
  return a;
}

void require_same_batch(VecEnv& a, VecEnv& b) {
  for (int i = 0; i < a.size(); ++i) REQUIRE(a.observation(i).values == b.observation(i).values);
}

}  // namespace

TEST_CASE("VecEnv of remote envs: all requests in flight at once, the same steps and resets as local envs",
          "[remote][vec_env]") {
  Served served("vec_env_pipelined");
  const EnvConfig config = short_jaka();
  const int n = 5;
  for (int threads : {1, 2}) {
    INFO("threads " << threads);
    VecEnv local(local_envs(config, n), 11, 20, threads);
    VecEnv remote(remote_envs(served.link(), config, n), 11, 20, threads);
    require_same_batch(remote, local);
    for (int t = 0; t < 60; ++t) {
      const auto actions = actions_at(t, n);
      const auto& r = remote.step(actions);
      const auto& l = local.step(actions);
      for (int i = 0; i < n; ++i) {
        REQUIRE(r[static_cast<std::size_t>(i)].reward == l[static_cast<std::size_t>(i)].reward);
        REQUIRE(r[static_cast<std::size_t>(i)].truncated == l[static_cast<std::size_t>(i)].truncated);
        REQUIRE(r[static_cast<std::size_t>(i)].final_observation.values ==
                l[static_cast<std::size_t>(i)].final_observation.values);
      }
      require_same_batch(remote, local);
    }
    CHECK(remote.episodes().episodes() == local.episodes().episodes());
    CHECK(local.episodes().episodes() >= n * 2);
  }
}

TEST_CASE("VecEnv of remote envs: a refused action is an error and every env's next step still works",
          "[remote][vec_env]") {
  Served served("vec_env_refused");
  const EnvConfig config = short_jaka();
  const int n = 4;
  VecEnv local(local_envs(config, n), 5, 20, 1);
  VecEnv remote(remote_envs(served.link(), config, n), 5, 20, 1);
  // The last env's action is out of range: a local env refuses it before moving and after the
  // envs before it stepped; the server refuses it the same way while the others' steps complete.
  auto bad = actions_at(0, n);
  bad.back() = Action::discrete(9);
  CHECK_THROWS_AS(local.step(bad), Error);
  CHECK_THROWS_WITH(remote.step(bad), Contains("action"));
  require_same_batch(remote, local);
  for (int t = 1; t < 30; ++t) {
    const auto actions = actions_at(t, n);
    remote.step(actions);
    local.step(actions);
    require_same_batch(remote, local);
  }
}

TEST_CASE("RemoteEnv: a begun step must be finished before the next request, and equals step()", "[remote][vec_env]") {
  Served served("vec_env_split");
  const EnvConfig config = short_jaka();
  const auto remote = connect_remote_env(served.link(), config);
  const auto local = make_env(config);
  CHECK(remote->reset(4).values == local->reset(4).values);
  CHECK_FALSE(local->begin_step(Action::discrete(1)));  // a local env does not split a step
  CHECK_THROWS_WITH(local->finish_step(ObservationOut{}), Contains("without a step begun"));
  REQUIRE(remote->begin_step(Action::discrete(1)));
  CHECK_THROWS_WITH(remote->begin_step(Action::discrete(1)), Contains("before the step begun was finished"));
  CHECK_THROWS_WITH(remote->reset(), Contains("before the step begun was finished"));
  Observation obs = make_observation(remote->spec().observation);
  const StepOutcome o = remote->finish_step(observation_out(obs));
  const StepResult l = local->step(Action::discrete(1));
  CHECK(obs.values == l.observation.values);
  CHECK(o.reward == l.reward);
  CHECK_THROWS_WITH(remote->finish_step(observation_out(obs)), Contains("without a step begun"));
  CHECK(remote->step(Action::discrete(2)).observation.values == local->step(Action::discrete(2)).observation.values);
}

TEST_CASE("VecEnv of remote envs: drop_caches reaches the server's envs, so long runs stay identical to local ones",
          "[remote][vec_env]") {
  Served served("vec_env_caches");
  EnvConfig config = default_env_config("jaka_button");
  config.get<ReachOptions>().random_target = true;
  const int n = 8;
  VecEnv local(local_envs(config, n), 3, 20, 1);
  VecEnv remote(remote_envs(served.link(), config, n), 3, 20, 1);
  // Mostly down (action 4: -z), pressing the effector on the floor, with random moves: contacts
  // that last across the drop points, where Bullet's contact caches change later steps unless
  // both sides drop them at the same time.
  Rng rng(17);
  for (int t = 0; t < 1500; ++t) {
    std::vector<Action> actions;
    for (int i = 0; i < n; ++i) actions.push_back(Action::discrete(rng.below(3) == 0 ? static_cast<int>(rng.below(6)) : 4));
    remote.step(actions);
    local.step(actions);
    require_same_batch(remote, local);
    if (t % 16 == 15) {  // an update boundary of `rdsim train`
      remote.drop_caches();
      local.drop_caches();
    }
  }
  CHECK(local.episodes().episodes() > 10);
}
