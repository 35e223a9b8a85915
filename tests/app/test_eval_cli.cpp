// Periodic evaluation (the config's "eval" object; issue #45) through the real binary: eval.csv and a
// best_model.bin whose replay is the best evaluation, training unchanged by it, the schedule kept
// exactly across kill -9 and --resume and under mpirun, and one clear error for each misuse.
#include <catch2/catch.hpp>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "process_util.hpp"
#include "rdsim/training/model_file.hpp"
#include "rl_test_util.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;
using namespace std::chrono_literals;

namespace {

// PPO on jaka_button for 20480 steps (under a second), with or without evaluations every 4096 steps.
std::string ppo_config(const ScratchDir& dir, const std::string& name, bool eval) {
  const std::string path = dir / (name + ".json");
  rltest::spit(path, R"({"algorithm": "ppo", "env": {"name": "jaka_button", "is_discrete": true, "random_target": true},
    "seed": 3, "total_timesteps": 20000, "num_envs": 8, "network": {"hidden_sizes": [64, 64], "activation": "tanh"},
    "ppo": {"n_steps": 256, "batch_size": 256, "learning_rate": 0.003, "gamma": 0.98})" +
                         std::string(eval ? R"(, "eval": {"every": 4096, "episodes": 5}})" : "}"));
  return path;
}

// eval.csv without its `seconds` column (the wall time of each evaluation).
std::string eval_rows(const std::string& run) { return rltest::drop_columns(rltest::slurp(run + "/eval.csv"), 1); }

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t comma; (comma = line.find(',', from)) != std::string::npos; from = comma + 1)
    out.push_back(line.substr(from, comma - from));
  out.push_back(line.substr(from));
  return out;
}

std::string two_decimals(const std::string& number) {
  char text[64];
  std::snprintf(text, sizeof text, "%.2f", std::stod(number));
  return text;
}

}  // namespace

TEST_CASE("eval: PPO on jaka_button writes eval.csv and a best_model.bin whose replay is the best evaluation, training unchanged",
          "[cli][eval]") {
  ScratchDir dir("eval_ppo");
  for (const bool eval : {false, true}) {
    const std::string name = eval ? "eval" : "plain";
    const auto r = run_rdsim("train --config " + ppo_config(dir, name, eval) + " --log-dir " + (dir / name), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    if (eval) CHECK_THAT(r.err, Contains("eval at 4096 steps: mean return") && Contains("new best"));
  }
  // The evaluations draw nothing from the run's streams: the training logs and weights are the same.
  CHECK(rltest::run_logs(dir / "eval") == rltest::run_logs(dir / "plain"));
  CHECK_FALSE(fs::exists(dir / "plain/eval.csv"));

  const auto rows = rltest::lines(rltest::slurp(dir / "eval/eval.csv"));
  REQUIRE(rows.size() == 6);  // the header, then 4096, 8192, ..., 20480
  CHECK(rows[0] == "timesteps,episodes,mean_return,std_return,min_return,max_return,mean_length,success_rate,new_best,seconds");
  std::string best_return, best_success;
  double best = -1e300;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto c = cells(rows[k]);
    CHECK(std::stoll(c[0]) == 4096 * static_cast<long long>(k));
    CHECK(c[1] == "5");
    const bool improves = std::stod(c[2]) > best;
    CHECK(c[8] == (improves ? "1" : "0"));
    if (improves) {
      best = std::stod(c[2]);
      best_return = c[2];
      best_success = c[7];
    }
  }
  // `rdsim replay best_model.bin --episodes 5` runs the same five episodes as the best evaluation.
  const auto replay = run_rdsim("replay " + (dir / "eval/best_model.bin") + " --episodes 5", dir);
  INFO(replay.out << replay.err);
  REQUIRE(replay.exit_code == 0);
  CHECK_THAT(replay.out, Contains("mean return " + two_decimals(best_return) + ",") &&
                             Contains("success rate " + two_decimals(best_success) + " over 5 episodes"));
  const auto config = nlohmann::json::parse(rltest::slurp(dir / "eval/config.json"));
  CHECK(config["eval"]["every"] == 4096);
  CHECK(config["eval"]["episodes"] == 5);
}

TEST_CASE("eval: after kill -9 and --resume the evaluations and best_model.bin of an uninterrupted run", "[cli][eval]") {
  ScratchDir dir("eval_resume");
  // TD3 on reach_goal: slow enough (about 2 s) to be killed after its first checkpoint.
  const std::string config = dir / "td3.json";
  rltest::spit(config, R"({"algorithm": "td3", "env": {"name": "reach_goal", "max_steps": 20}, "seed": 4,
    "total_timesteps": 12000, "num_envs": 2, "checkpoint_interval": 2000, "network": {"hidden_sizes": [32, 32]},
    "td3": {"learning_starts": 200, "batch_size": 64, "buffer_size": 5000}, "eval": {"every": 1500, "episodes": 4}})");
  auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "whole"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::lines(rltest::slurp(dir / "whole/eval.csv")).size() == 9);  // 1500, 3000, ..., 12000

  const std::string run = dir / "killed";
  proctest::kill_and_resume(config, run, dir, 300ms);
  CHECK(eval_rows(run) == eval_rows(dir / "whole"));
  CHECK(rltest::run_logs(run) == rltest::run_logs(dir / "whole"));
  CHECK(rdsim::read_model_file(run + "/best_model.bin").payload == rdsim::read_model_file(dir / "whole/best_model.bin").payload);
}

#ifdef RDSIM_MPIEXEC
TEST_CASE("eval: mpirun -np 2 evaluates on rank 0, the same eval.csv twice", "[cli][eval][mpi]") {
  ScratchDir dir("eval_mpi");
  const std::string config = ppo_config(dir, "ppo", true);
  rltest::train_twice_on_two_ranks(config, dir);
  CHECK(eval_rows(dir / "a") == eval_rows(dir / "b"));
  CHECK(rltest::lines(rltest::slurp(dir / "a/eval.csv")).size() == 6);
  CHECK(fs::exists(dir / "a/best_model.bin"));
}
#endif

TEST_CASE("eval: misuse is one clear error naming the config and the key", "[cli][eval]") {
  ScratchDir dir("eval_errors");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"env": {"name": "cartpole"}, "eval": {"every": 0}})", "eval.every"},
      {R"({"env": {"name": "cartpole"}, "eval": {"episodes": 0}})", "eval.episodes"},
      {R"({"env": {"name": "cartpole"}, "eval": {"every": 1000, "n_episodes": 5}})", "n_episodes"},
      {R"({"env": {"name": "cartpole"}, "eval": 1000})", "eval"},
  };
  rltest::check_config_errors(dir, cases);
}
