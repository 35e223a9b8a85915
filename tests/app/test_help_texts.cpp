// Help texts say what the commands do, and errors point at the right command's help.
#include <catch2/catch.hpp>

#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;

TEST_CASE("help: bench-fps --json takes an optional FILE and is off by default", "[cli][help]") {
  ScratchDir dir("help_bench");
  const auto r = run_rdsim("bench-fps --help", dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("--json [FILE]"));
  CHECK_THAT(r.out, !Contains("TEXT=-"));
}

TEST_CASE("help: seeds and timesteps are integers", "[cli][help]") {
  ScratchDir dir("help_seed");
  for (const char* command : {"train", "replay", "render"}) {
    INFO(command);
    const auto r = run_rdsim(std::string(command) + " --help", dir);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.out, Contains("--seed INT"));
    CHECK_THAT(r.out, !Contains("--seed TEXT"));
  }
  CHECK_THAT(run_rdsim("train --help", dir).out, Contains("--timesteps INT"));
}

TEST_CASE("demos record: the scripted expert records without --expert, errors point at its own help", "[cli][help][demos]") {
  ScratchDir dir("help_demos");
  auto r = run_rdsim("demos record --help", dir);
  REQUIRE(r.exit_code == 0);
  const auto at = r.out.find("--expert");
  REQUIRE(at != std::string::npos);
  const std::string expert_line = r.out.substr(at, r.out.find('\n', at) - at);
  CHECK_THAT(expert_line, !Contains("REQUIRED"));
  r = run_rdsim("demos record --env jaka_button -n 2 -q --out " + dir / "new/x.demo", dir);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("wrote 2 scripted episodes"));
  r = run_rdsim("demos record --env jaka_button -n 2", dir);  // --out missing
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("--out") && Contains("(rdsim demos record --help)"));
}

TEST_CASE("an unknown command names the closest one", "[cli][suggest]") {
  ScratchDir dir("help_suggest");
  auto r = run_rdsim("trian", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("unknown command \"trian\" (did you mean \"train\"?)"));
  r = run_rdsim("Plot", dir);
  CHECK_THAT(r.err, Contains("(did you mean \"plot\"?)"));
  r = run_rdsim("frobnicate", dir);
  CHECK_THAT(r.err, !Contains("did you mean"));
}
