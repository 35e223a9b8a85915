// The scripted expert of the reaching envs (rdsim demos record --expert): it solves every task with
// the env's own actions, Discrete and Box.
#include <catch2/catch.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/reach_expert.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;

TEST_CASE("the scripted expert solves every reaching task with the env's own actions", "[envs][expert]") {
  for (const char* name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    for (bool discrete : {true, false}) {
      INFO(name << (discrete ? " Discrete" : " Box"));
      EnvConfig config = default_env_config(name);
      config.get<ReachOptions>().random_target = true;
      config.is_discrete = discrete;
      auto env = make_env(config);
      ReachExpert expert(*env);
      int successes = 0, collisions = 0;
      const int episodes = 12;
      for (int k = 0; k < episodes; ++k) {
        env->reset(500 + static_cast<std::uint64_t>(k));
        expert.reset();
        for (bool done = false; !done;) {
          const Action a = expert.act();
          CHECK(a.values.size() == (discrete ? 0 : 3));
          const StepResult r = env->step(a);
          successes += r.info.success;
          collisions += r.info.collision;
          done = r.terminated || r.truncated;
        }
      }
      CHECK(successes == episodes);
      CHECK(collisions == 0);
    }
  }
  auto cartpole = make_env(default_env_config("cartpole"));
  CHECK_THROWS_WITH(ReachExpert(*cartpole), Contains("env cartpole has no scripted expert"));
}
