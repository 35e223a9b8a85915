// "normalize_observations" (issue #45) through the real binary: the same CSVs on 1 and 2 threads, after
// kill -9 and --resume and under mpirun; the model replays; one clear error for each misuse. The
// transform itself and the model files of every algorithm: tests/algorithms/test_observation_normalizer.cpp;
// Python predict against replay: tests/python/test_normalize.py.
#include <catch2/catch.hpp>

#include <csignal>
#include <filesystem>
#include <thread>

#include "process_util.hpp"
#include "rl_test_util.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using rltest::run_logs;
using rltest::run_rdsim;
using rltest::ScratchDir;
using namespace std::chrono_literals;

namespace {

std::string write_config(const ScratchDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir / (name + ".json");
  rltest::spit(path, text);
  return path;
}

// PPO on jaka_button (8 envs, under a second) and SAC + HER on reach_goal (about 2 s, checkpoints every 2000 steps).
const char* ppo_text = R"({"algorithm": "ppo", "env": {"name": "jaka_button", "is_discrete": true, "random_target": true},
  "seed": 2, "total_timesteps": 12000, "num_envs": 8, "normalize_observations": true,
  "network": {"hidden_sizes": [32, 32], "activation": "tanh"}, "ppo": {"n_steps": 128, "batch_size": 256}})";
const char* sac_text = R"({"algorithm": "sac", "env": {"name": "reach_goal", "max_steps": 20}, "seed": 4,
  "total_timesteps": 10000, "num_envs": 2, "checkpoint_interval": 2000, "normalize_observations": true,
  "network": {"hidden_sizes": [32, 32]}, "sac": {"learning_starts": 200, "batch_size": 64, "buffer_size": 5000},
  "her": {}})";

}  // namespace

TEST_CASE("normalize_observations: the same CSVs on 1 and 2 threads, and the model replays", "[cli][normalize]") {
  ScratchDir dir("normalize_threads");
  for (const auto& [name, text] : {std::pair{"ppo", ppo_text}, std::pair{"sac", sac_text}}) {
    const std::string config = write_config(dir, name, text);
    for (const std::string threads : {"1", "2"}) {
      const auto r = run_rdsim("train --quiet --config " + config + " --threads " + threads + " --log-dir " +
                                   (dir / (name + std::string("_t") + threads)),
                               dir);
      INFO(r.err);
      REQUIRE(r.exit_code == 0);
    }
    CHECK(run_logs(dir / (name + std::string("_t1"))) == run_logs(dir / (name + std::string("_t2"))));
    const auto config_json = nlohmann::json::parse(rltest::slurp(dir / (name + std::string("_t1/config.json"))));
    CHECK(config_json["normalize_observations"] == true);
    const auto replay = run_rdsim("replay " + (dir / (name + std::string("_t1/model.bin"))) + " --episodes 3", dir);
    INFO(replay.err);
    CHECK(replay.exit_code == 0);
    CHECK_THAT(replay.out, Contains("over 3 episodes"));
  }
}

TEST_CASE("normalize_observations: after kill -9 and --resume the run of one never killed", "[cli][normalize]") {
  ScratchDir dir("normalize_resume");
  const std::string config = write_config(dir, "sac", sac_text);
  auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "whole"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string run = dir / "killed";
  proctest::kill_and_resume(config, run, dir, 300ms);
  CHECK(run_logs(run) == run_logs(dir / "whole"));
}

#ifdef RDSIM_MPIEXEC
TEST_CASE("normalize_observations: mpirun -np 2 keeps the ranks' statistics the same, the same CSV twice", "[cli][normalize][mpi]") {
  ScratchDir dir("normalize_mpi");
  const std::string config = write_config(dir, "ppo", ppo_text);
  rltest::train_twice_on_two_ranks(config, dir);  // each ends comparing the ranks' weights and transform
  CHECK(run_logs(dir / "a") == run_logs(dir / "b"));
}
#endif

TEST_CASE("normalize_observations: misuse is one clear error naming the config and the key", "[cli][normalize]") {
  ScratchDir dir("normalize_errors");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"algorithm": "ars", "env": {"name": "cartpole"}, "normalize_observations": true})",
       "normalize_observations: has no effect with \"algorithm\": \"ars\" (it has its own: ars.normalize_observations)"},
      {R"({"algorithm": "random", "env": {"name": "cartpole"}, "normalize_observations": true})", "ppo, a2c, trpo, dqn, sac, td3 and ddpg"},
      {R"({"env": {"name": "jaka_button", "observation": "raw_pixels"}, "normalize_observations": true})", "only for vector observations"},
      {R"({"env": {"name": "cartpole"}, "normalize_observations": true, "network": {"input_scale": 0.1}})", "network.input_scale"},
      {R"({"env": {"name": "cartpole"}, "normalize_observations": "yes"})", "normalize_observations"},
      {R"({"env": {"name": "cartpole"}, "normalize_observations": true, "demonstrations": {"file": "x.demo"}})",
       "cannot be combined with demonstrations for ppo (its pre-training would see other inputs than its training); "
       "sac, td3 and ddpg take both"},
  };
  rltest::check_config_errors(dir, cases);
}
