// docs/config.md is `rdsim config-reference`'s output: the key tables in the code and the
// document cannot drift apart.
#include <catch2/catch.hpp>
#include <string>

#include "rdsim/app/config_reference.hpp"
#include "rdsim/envs/registry.hpp"
#include "rl_test_util.hpp"

TEST_CASE("docs/config.md is up to date with the config keys", "[app][docs]") {
  const std::string path = std::string(RDSIM_SOURCE_DIR) + "/docs/config.md";
  const std::string doc = rltest::slurp(path);
  const bool up_to_date = doc == rdsim::config_reference();
  if (!up_to_date)
    FAIL(path + " differs from `rdsim config-reference`: regenerate it with "
                "`build/rdsim config-reference > docs/config.md` and commit it");
}

TEST_CASE("rdsim config-reference prints the reference, with every env's defaults", "[app][docs]") {
  rltest::ScratchDir dir("config_reference");
  const auto r = rltest::run_rdsim("config-reference", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out == rdsim::config_reference());
  for (const auto& e : rdsim::env_registry()) CHECK_THAT(r.out, Catch::Contains("| " + e.name + " |"));
  // jaka_button's own action_step, not a generic one, and keys cartpole and pendulum do not read marked.
  CHECK_THAT(r.out, Catch::Contains("`action_step` | number | 0.0001 … 2 | — | — | `0.015` | `0.015` | `0.004` |"));
  CHECK_THAT(r.out, Catch::Contains("## `ppo`") && Catch::Contains("## `a2c`") && Catch::Contains("## `dqn`"));
}
