// Domain randomization ("randomize" in the env object, issue #43 item 1) through the real binary:
// the same CSVs for the same seed on 1 and 2 threads, after kill -9 and
// --resume the run of one never killed, and one clear error per misuse. The randomization itself:
// tests/envs/test_randomization.cpp.
#include <catch2/catch.hpp>

#include "process_util.hpp"
#include "rl_test_util.hpp"

using rltest::run_logs;
using rltest::run_rdsim;
using rltest::ScratchDir;
using namespace std::chrono_literals;

namespace {

// PPO on jaka_button with 2 steps of latency, 5 mm of noise and every per-episode draw a reaching task
// has (about a second), checkpoints every 2048 steps.
const char* ppo_text = R"({"algorithm": "ppo", "env": {"name": "jaka_button", "random_target": true,
  "randomize": {"action_latency": 2, "observation_noise": 0.005, "mass_scale": [0.7, 1.3], "friction_scale": [0.5, 1.5],
  "joint_damping": [0, 0.5], "gain_scale": [0.8, 1.2], "placement_noise": 0.01}}, "seed": 6, "total_timesteps": 40960, "num_envs": 4,
  "checkpoint_interval": 2048, "network": {"hidden_sizes": [32, 32]}, "ppo": {"n_steps": 256, "batch_size": 256}})";

}  // namespace

TEST_CASE("randomize: the same seed gives the same CSVs on 1 and 2 threads", "[cli][randomize]") {
  ScratchDir dir("randomize_threads");
  const std::string config = dir / "ppo.json";
  rltest::spit(config, ppo_text);
  for (const std::string threads : {"1", "2"}) {
    const auto r = run_rdsim("train --quiet --config " + config + " --threads " + threads + " --log-dir " + (dir / ("t" + threads)), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  CHECK(run_logs(dir / "t1") == run_logs(dir / "t2"));
  // Not the run without randomization: the option is in effect.
  nlohmann::json plain = nlohmann::json::parse(ppo_text);
  plain["env"].erase("randomize");
  rltest::spit(dir / "plain.json", plain.dump());
  REQUIRE(run_rdsim("train --quiet --config " + (dir / "plain.json") + " --log-dir " + (dir / "plain"), dir).exit_code == 0);
  CHECK_FALSE(run_logs(dir / "t1") == run_logs(dir / "plain"));
}

TEST_CASE("randomize: after kill -9 and --resume the run of one never killed", "[cli][randomize]") {
  ScratchDir dir("randomize_resume");
  const std::string config = dir / "ppo.json";
  rltest::spit(config, ppo_text);
  auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "whole"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string run = dir / "killed";
  proctest::kill_and_resume(config, run, dir, 20ms);
  CHECK(run_logs(run) == run_logs(dir / "whole"));
}

TEST_CASE("randomize: misuse is one clear error naming the config and the key", "[cli][randomize]") {
  ScratchDir dir("randomize_errors");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"env": {"name": "jaka_button", "randomize": {"observation_noise": -1}}})", "env.randomize.observation_noise"},
      {R"({"env": {"name": "jaka_button", "randomize": {"friction": [0.5, 1.5]}}})", "env.randomize.friction"},
      {R"({"env": {"name": "jaka_button", "max_steps": 20, "randomize": {"action_latency": 25}}})",
       "env.randomize.action_latency: 25 steps is not shorter than"},
      {R"({"env": {"name": "cartpole", "randomize": {"action_latency": 1}}})", "env.randomize"},
      {R"({"env": {"name": "jaka_button", "randomize": {"mass_scale": [1.3, 0.7]}}})",
       "env.randomize.mass_scale: expected [lo, hi] with lo <= hi"},
      {R"({"env": {"name": "jaka_button", "randomize": {"camera_shift": 0.03}}})",
       "env.randomize.camera_shift: applies to raw-pixel observations only"},
  };
  rltest::check_config_errors(dir, cases);
}
