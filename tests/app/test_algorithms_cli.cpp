// Every algorithm through the real binary, as a user runs it: same seed gives the same logs,
// `rdsim replay` runs the saved model, and an interrupted off-policy run resumes exactly.
#include <catch2/catch.hpp>

#include "rdsim/training/model_file.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

struct TinyRun {
  const char* algorithm;
  const char* env;
  const char* params;  // the algorithm's object
};

// A few hundred steps of each algorithm on its validation env.
const TinyRun tiny_runs[] = {
    {"sac", R"({"name": "pendulum"})", R"({"learning_starts": 100, "batch_size": 32, "buffer_size": 1000})"},
    {"td3", R"({"name": "pendulum"})", R"({"learning_starts": 100, "batch_size": 32, "buffer_size": 1000})"},
    {"ddpg", R"({"name": "pendulum"})",
     R"({"learning_starts": 100, "batch_size": 32, "buffer_size": 1000, "action_noise": "ornstein_uhlenbeck"})"},
    {"trpo", R"({"name": "cartpole"})", R"({"n_steps": 100, "batch_size": 50, "n_critic_updates": 2})"},
    {"ars", R"({"name": "cartpole"})", R"({"n_delta": 2})"},
    {"cma_es", R"({"name": "cartpole"})", R"({"population_size": 4})"},
    {"random", R"({"name": "pendulum"})", R"({"n_steps": 100})"},
};

std::string tiny_config(const ScratchDir& dir, const TinyRun& run, long long interval = 0) {
  const std::string path = dir / (std::string(run.algorithm) + ".json");
  rltest::spit(path, std::string(R"({"algorithm": ")") + run.algorithm + R"(", "env": )" + run.env +
                         R"(, "seed": 5, "total_timesteps": 600, "num_envs": 2, "checkpoint_interval": )" +
                         std::to_string(interval) + R"(, "network": {"hidden_sizes": [16]}, ")" + run.algorithm +
                         R"(": )" + run.params + "}");
  return path;
}

}  // namespace

TEST_CASE("every algorithm trains, repeats itself with one seed, and replays from its model", "[cli][algorithms]") {
  ScratchDir dir("cli_algorithms");
  for (const TinyRun& run : tiny_runs) {
    INFO(run.algorithm);
    const std::string config = tiny_config(dir, run);
    const std::string a = dir / (std::string(run.algorithm) + "_a"), b = dir / (std::string(run.algorithm) + "_b");
    for (const std::string& out : {a, b}) {
      const auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + out, dir);
      INFO(r.err);
      REQUIRE(r.exit_code == 0);
    }
    const std::string progress = rltest::slurp(a + "/progress.csv");
    CHECK(rltest::lines(progress).size() > 1);
    CHECK(rltest::drop_columns(progress, 2) == rltest::drop_columns(rltest::slurp(b + "/progress.csv"), 2));
    CHECK(rltest::drop_columns(rltest::slurp(a + "/episodes.csv"), 1) ==
          rltest::drop_columns(rltest::slurp(b + "/episodes.csv"), 1));
    CHECK_THAT(rltest::slurp(a + "/config.json"), Contains(std::string("\"algorithm\": \"") + run.algorithm + "\""));

    const auto r = run_rdsim("replay " + a + "/model.bin -n 2", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.out, Contains(std::string("(") + run.algorithm + " on "));
    CHECK_THAT(r.out, Contains("episode 2: return"));
    CHECK(run_rdsim("replay " + a + "/checkpoint.bin -n 2", dir).out.find("mean return") != std::string::npos);
  }
}

TEST_CASE("train --resume continues SAC and ARS runs exactly", "[cli][algorithms]") {
  ScratchDir dir("cli_algorithms_resume");
  for (const TinyRun& run : {tiny_runs[0], tiny_runs[4]}) {
    INFO(run.algorithm);
    const std::string config = tiny_config(dir, run, 300);
    const std::string full = dir / (std::string(run.algorithm) + "_full"), part = dir / (std::string(run.algorithm) + "_part");
    auto r = run_rdsim("train --quiet --config " + config + " --timesteps 900 --log-dir " + full, dir);
    REQUIRE(r.exit_code == 0);
    r = run_rdsim("train --quiet --config " + config + " --log-dir " + part, dir);
    REQUIRE(r.exit_code == 0);
    r = run_rdsim("train --quiet --resume " + part + " --timesteps 900", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(rltest::drop_columns(rltest::slurp(part + "/progress.csv"), 2) ==
          rltest::drop_columns(rltest::slurp(full + "/progress.csv"), 2));
    CHECK((rdsim::read_model_file(part + "/model.bin").payload == rdsim::read_model_file(full + "/model.bin").payload));
  }
}

TEST_CASE("algorithms that cannot handle an env's spaces say so", "[cli][algorithms]") {
  ScratchDir dir("cli_algorithms_spaces");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"algorithm": "sac", "env": {"name": "cartpole"}})", "continuous (Box) action space"},
      {R"({"algorithm": "dqn", "env": {"name": "pendulum"}})", "discrete action space"},
      {R"({"algorithm": "td3", "env": {"name": "jaka_button", "observation": "raw_pixels", "is_discrete": false},
            "td3": {"buffer_size": 1000}})",  // a small buffer: the default one of images is refused for memory first
       "vector observations"},
      {R"({"algorithm": "cma_es", "env": {"name": "cartpole"}, "network": {"hidden_sizes": [64, 64]}})", "at most 2000"},
      {R"({"algorithm": "trpo", "env": {"name": "cartpole"}, "network": {"shared": true}})", "network.shared"},
  };
  rltest::check_config_errors(dir, cases);
}
