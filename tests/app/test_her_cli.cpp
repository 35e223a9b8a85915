// Hindsight experience replay through the real binary (issue #42): the CI-sized learning checks on
// reach_goal (SAC, and DQN on its Discrete moves), the same CSVs on any thread count, after kill -9
// and --resume, under mpirun and through a remote env, and one clear error for each misuse. The long
// learning runs are tools/bench/her.sh.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <thread>

#include "../remote/remote_test_util.hpp"
#include "process_util.hpp"
#include "rdsim/training/model_file.hpp"
#include "rl_test_util.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;
using namespace std::chrono_literals;

namespace {

// A short TD3 + HER run on reach_goal (about 2 s): 2 envs, episodes of 20 steps, checkpoints every
// 2000 steps; with `algorithm` "dqn" the same on reach_goal's Discrete(6) moves.
std::string small_config(const ScratchDir& dir, const std::string& name, const std::string& env_extra = "",
                         const std::string& algorithm = "td3") {
  const std::string path = dir / (name + ".json");
  const bool dqn = algorithm == "dqn";
  rltest::spit(path, R"({"algorithm": ")" + algorithm + R"(", "env": {"name": "reach_goal", "max_steps": 20)" +
                         (dqn ? ", \"is_discrete\": true" : "") + env_extra +
                         R"(}, "seed": 4, "total_timesteps": 12000, "num_envs": 2, "checkpoint_interval": 2000,
    "network": {"hidden_sizes": [32, 32]}, ")" + algorithm + R"(": {"learning_starts": 200, "batch_size": 64, "buffer_size": 5000},
    "her": {"n_sampled_goal": 4, "goal_selection_strategy": "future"}})");
  return path;
}

using rltest::run_logs;

// A short SAC + HER run on push (2 envs, networks of 16 x 16) with the "demonstrations" object's
// keys `demos` (JSON without braces), in dir/run (its config beside it as run.json).
void train_push_with_demos(const ScratchDir& dir, const std::string& run, const std::string& demos, int timesteps) {
  const std::string path = dir / (run + ".json");
  rltest::spit(path, R"({"algorithm": "sac", "env": {"name": "push"}, "seed": 5, "total_timesteps": )" +
                         std::to_string(timesteps) + R"(, "num_envs": 2, "network": {"hidden_sizes": [16, 16]},
    "sac": {"learning_starts": 200, "batch_size": 32, "buffer_size": 2000}, "her": {}, "demonstrations": {)" + demos + "}}");
  const auto r = run_rdsim("train --quiet --config " + path + " --log-dir " + (dir / run), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
}

// `n` episodes of `env`'s scripted expert into DIR/ENV.demo.
void record_expert(const ScratchDir& dir, const std::string& env, int n) {
  const auto r = run_rdsim("demos record --quiet --expert --env " + env + " -n " + std::to_string(n) + " --out " +
                               (dir / (env + ".demo")),
                           dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
}

// A demonstrations key's runs: "plain" with `demos`, then NAME1 and NAME2 with `demos` + `extra`,
// which must give the same CSVs (the same seed).
void train_plain_and_twice(const ScratchDir& dir, const std::string& name, const std::string& demos, const std::string& extra,
                           int timesteps) {
  train_push_with_demos(dir, "plain", demos, timesteps);
  train_push_with_demos(dir, name + "1", demos + extra, timesteps);
  train_push_with_demos(dir, name + "2", demos + extra, timesteps);
  CHECK(run_logs(dir / (name + "1")) == run_logs(dir / (name + "2")));
}

// A demonstrations key that changes the demonstrated transitions drawn into minibatches: push's
// expert (4 episodes) trained on plain and twice with `extra`; the pre-training's losses already
// differ from the plain run's.
void train_on_changed_batches(const ScratchDir& dir, const std::string& name, const std::string& extra) {
  record_expert(dir, "push", 4);
  const std::string demos = R"("file": "push.demo", "bc_epochs": 2, "demo_fraction": 0.5)";
  train_plain_and_twice(dir, name, demos, extra, 400);
  CHECK(rltest::slurp(dir / (name + "1/pretrain.csv")) != rltest::slurp(dir / "plain/pretrain.csv"));
}

// Success over the last `window` episodes of episodes.csv.
double final_success(const std::string& run, std::size_t window) {
  const auto rows = rltest::lines(rltest::slurp(run + "/episodes.csv"));
  REQUIRE(rows.size() > window);
  REQUIRE(rows.front().find(",success,") != std::string::npos);
  double sum = 0.0;
  for (std::size_t k = rows.size() - window; k < rows.size(); ++k) {
    std::string cell = rows[k];
    for (int c = 0; c < 4; ++c) cell = cell.substr(cell.find(',') + 1);  // episode,timesteps,return,length,
    sum += std::stod(cell.substr(0, cell.find(',')));
  }
  return sum / static_cast<double>(window);
}

}  // namespace

TEST_CASE("her: SAC + HER (configs/jaka_reach_goal.json) and DQN + HER on the Discrete moves (jaka_reach_goal_dqn.json) "
          "each learns reach_goal, 95 of the last 100 episodes succeed within 20k env steps",
          "[cli][her][learning]") {
  const std::string name = GENERATE("jaka_reach_goal", "jaka_reach_goal_dqn");
  INFO(name);
  ScratchDir dir("her_" + name);
  const auto r = run_rdsim("train --quiet --config configs/" + name + ".json --log-dir " + (dir / "run"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto config = nlohmann::json::parse(rltest::slurp(dir / "run/config.json"));
  CHECK(config["total_timesteps"].get<long long>() <= 20000);
  CHECK(config["her"]["n_sampled_goal"] == 4);
  CHECK(config["env"]["is_discrete"] == (config["algorithm"] == "dqn"));
  CHECK(final_success(dir / "run", 100) >= 0.95);
  CHECK_THAT(rltest::lines(rltest::slurp(dir / "run/progress.csv")).front(), Contains("her_relabelable"));
}

TEST_CASE("her: the same CSVs on 1 and 2 threads, and after kill -9 and --resume", "[cli][her]") {
  const std::string algorithm = GENERATE("td3", "dqn");
  INFO(algorithm);
  ScratchDir dir("her_determinism_" + algorithm);
  const std::string config = small_config(dir, algorithm + "_her", "", algorithm);
  for (const std::string threads : {"1", "2"}) {
    const auto r = run_rdsim("train --quiet --config " + config + " --threads " + threads + " --log-dir " + (dir / ("t" + threads)), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  CHECK(run_logs(dir / "t1") == run_logs(dir / "t2"));
  CHECK(rltest::lines(rltest::slurp(dir / "t1/episodes.csv")).size() > 50);

  // Killed once a checkpoint exists, resumed: the run of one that was never killed.
  const std::string run = dir / "killed";
  proctest::kill_and_resume(config, run, dir, 100ms);
  CHECK(run_logs(run) == run_logs(dir / "t1"));
}

#ifdef RDSIM_MPIEXEC
TEST_CASE("her: mpirun -np 2 trains data-parallel, the same CSV twice", "[cli][her][mpi]") {
  const std::string algorithm = GENERATE("td3", "dqn");
  INFO(algorithm);
  ScratchDir dir("her_mpi_" + algorithm);
  const std::string config = small_config(dir, algorithm + "_her", "", algorithm);
  rltest::train_twice_on_two_ranks(config, dir);
  CHECK(run_logs(dir / "a") == run_logs(dir / "b"));
  CHECK(rltest::lines(rltest::slurp(dir / "a/progress.csv")).back().rfind("12000,", 0) == 0);
}
#endif

TEST_CASE("her: through a remote env (CurveZMQ) the logs of a local env", "[cli][her][remote]") {
  ScratchDir dir("her_remote");
  rdsim::test::Scratch keydir("her_remote_keys");
  rdsim::test::TestKeys keys(keydir);
  rdsim::test::ServerThread server(rdsim::test::curve_options(keys));
  const std::string local = small_config(dir, "local");
  const std::string remote = small_config(dir, "remote",
                                          ", \"remote\": \"" + server.endpoint() + "\", \"server_key\": \"" +
                                              keys.server_public + "\", \"client_key\": \"" + keys.client_secret + "\"");
  for (const auto& [config, name] : {std::pair{local, "local"}, std::pair{remote, "remote"}}) {
    const auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / name), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  CHECK(run_logs(dir / "remote") == run_logs(dir / "local"));
}

TEST_CASE("her: misuse is one clear error naming the config and the key", "[cli][her]") {
  ScratchDir dir("her_errors");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"algorithm": "ppo", "env": {"name": "reach_goal"}, "her": {}})", "her: has no effect with \"algorithm\": \"ppo\""},
      {R"({"algorithm": "a2c", "env": {"name": "reach_goal"}, "her": {}})", "sac, td3, ddpg or dqn"},
      {R"({"algorithm": "dqn", "env": {"name": "cartpole"}, "her": {}})", "her: env \"cartpole\" is not goal-conditioned"},
      {R"({"algorithm": "dqn", "env": {"name": "push"}, "her": {}})",
       "needs a discrete action space, env \"push\" has continuous actions (set env.is_discrete to true: reach_goal and push "
       "have Discrete(6) effector moves)"},
      {R"({"algorithm": "dqn", "env": {"name": "push", "is_discrete": true}, "her": {}, "dqn": {"n_step": 3}})",
       "dqn.n_step: expected 1 with \"her\""},
      {R"({"algorithm": "dqn", "env": {"name": "pick_and_place", "is_discrete": true}, "her": {}})",
       "env.is_discrete: pick_and_place with the fingers to move has Box actions only"},
      {R"({"algorithm": "sac", "env": {"name": "pendulum"}, "her": {}, "sac": {"buffer_size": 1000}})",
       "her: env \"pendulum\" is not goal-conditioned"},
      {R"({"algorithm": "sac", "env": {"name": "push"}, "her": {"n_sampled_goal": 0}})", "her.n_sampled_goal"},
      {R"({"algorithm": "td3", "env": {"name": "push"}, "her": {"goal_selection_strategy": "later"}})", "\"future\""},
      {R"({"algorithm": "td3", "env": {"name": "push"}, "her": {"n_sampled": 4}})", "n_sampled"},
  };
  rltest::check_config_errors(dir, cases);
}

TEST_CASE("her: the expert's demonstrations join a goal task's replay, and a file of another task is refused",
          "[cli][her][demos]") {
  ScratchDir dir("her_demos");
  for (const char* env : {"push", "pick_and_place"}) {
    const auto r = run_rdsim(std::string("demos record --quiet --expert --env ") + env + " -n 3 --out " + (dir / (std::string(env) + ".demo")), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  const auto config = [&](const std::string& demo_file, const std::string& extra) {
    const std::string path = dir / "push.json";
    rltest::spit(path, R"({"algorithm": "sac", "env": {"name": "push"}, "seed": 2, "total_timesteps": 600, "num_envs": 2,
      "network": {"hidden_sizes": [16, 16]}, "sac": {"learning_starts": 100, "batch_size": 32, "buffer_size": 2000},
      "her": {}, "demonstrations": {"file": ")" + demo_file + R"(", "bc_epochs": 4, "demo_fraction": 0.25, "bc_weight": 10)" +
                           extra + "}}");
    return path;
  };
  auto r = run_rdsim("train --quiet --config " + config(dir / "push.demo", "") + " --log-dir " + (dir / "run"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::lines(rltest::slurp(dir / "run/pretrain.csv")).size() == 1 + 4);
  CHECK_THAT(rltest::lines(rltest::slurp(dir / "run/progress.csv")).front(), Contains("bc_loss"));
  CHECK_THAT(rltest::slurp(dir / "run/config.json"), Contains("\"bc_weight\": 10"));

  r = run_rdsim("train --quiet --config " + config(dir / "pick_and_place.demo", "") + " --log-dir " + (dir / "other"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("pick_and_place.demo") && Contains("pick_and_place") && Contains("push"));

  r = run_rdsim("train --quiet --config " + config(dir / "push.demo", ", \"bc_weight_decay\": 0.9") + " --log-dir " + (dir / "decay"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("demonstrations.bc_weight_decay") && Contains("has no effect with \"algorithm\": \"sac\""));
}

TEST_CASE("her: episodes that start from the demonstrations' states give the same CSVs on 1 and 2 threads and after kill -9 "
          "and --resume, and bc refuses the key",
          "[cli][her][demos]") {
  ScratchDir dir("her_demo_starts");
  const std::string demo = dir / "push.demo";
  auto r = run_rdsim("demos record --quiet --expert --env push -n 4 --out " + demo, dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string config = dir / "starts.json";
  rltest::spit(config, R"({"algorithm": "sac", "env": {"name": "push"}, "seed": 5, "total_timesteps": 1200, "num_envs": 2,
    "checkpoint_interval": 400, "network": {"hidden_sizes": [16, 16]},
    "sac": {"learning_starts": 200, "batch_size": 32, "buffer_size": 4000}, "her": {},
    "demonstrations": {"file": ")" + demo + R"(", "bc_epochs": 2, "demo_fraction": 0.25, "start_fraction": 0.5}})");
  for (const std::string threads : {"1", "2"}) {
    r = run_rdsim("train --quiet --config " + config + " --threads " + threads + " --log-dir " + (dir / ("t" + threads)), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  CHECK(run_logs(dir / "t1") == run_logs(dir / "t2"));
  CHECK_THAT(rltest::slurp(dir / "t1/config.json"), Contains("\"start_fraction\": 0.5"));

  const std::string run = dir / "killed";
  proctest::kill_and_resume(config, run, dir, 50ms);
  CHECK(run_logs(run) == run_logs(dir / "t1"));

  rltest::check_config_errors(dir, {{R"({"algorithm": "bc", "env": {"name": "push"}, "demonstrations": {"file": ")" + demo +
                                         R"(", "start_fraction": 0.5}})",
                                     "demonstrations.start_fraction: has no effect with \"algorithm\": \"bc\""},
                                    {R"({"algorithm": "sac", "env": {"name": "push"}, "her": {}, "demonstrations": {"file": ")" +
                                         demo + R"(", "start_fraction": 1.5}})",
                                     "demonstrations.start_fraction"}});
}

TEST_CASE("her: demonstrations.start_file starts the episodes from another file's states, relative to the config's folder, "
          "and misuse is one clear error each",
          "[cli][her][demos]") {
  ScratchDir dir("her_start_file");
  for (const std::string seed : {"1000", "5000"}) {
    const auto r = run_rdsim("demos record --quiet --expert --env push -n 4 --seed " + seed + " --out " + (dir / ("s" + seed + ".demo")), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  const auto r0 = run_rdsim("demos record --quiet --expert --env pick_and_place -n 2 --out " + (dir / "pick.demo"), dir);
  REQUIRE(r0.exit_code == 0);
  // Every episode starts from a state of the demonstrations: which file they come from shows in episodes.csv.
  const std::string starts = R"("file": "s1000.demo", "bc_epochs": 2, "start_fraction": 1)";
  train_push_with_demos(dir, "own", starts, 600);
  train_push_with_demos(dir, "same", starts + R"(, "start_file": "s1000.demo")", 600);
  train_push_with_demos(dir, "other", starts + R"(, "start_file": "s5000.demo")", 600);
  CHECK(run_logs(dir / "same") == run_logs(dir / "own"));  // the same states: the same run
  CHECK(rltest::slurp(dir / "other/episodes.csv") != rltest::slurp(dir / "own/episodes.csv"));
  const auto recorded = nlohmann::json::parse(rltest::slurp(dir / "other/config.json"));
  CHECK(recorded["demonstrations"]["start_file"] == (dir / "s5000.demo"));  // absolute, for --resume from anywhere
  CHECK(recorded["demonstrations"]["file"] == (dir / "s1000.demo"));

  const std::string a = dir / "s1000.demo";
  const std::string head = R"({"algorithm": "sac", "env": {"name": "push"}, "her": {}, "demonstrations": {"file": ")" + a + R"(", )";
  rltest::check_config_errors(
      dir, {{head + R"("start_fraction": 0.5, "start_file": ")" + (dir / "pick.demo") + R"("}})",
             "demonstrations.start_file: " + (dir / "pick.demo") + ": these demonstrations do not fit the env"},
            {head + R"("start_fraction": 0.5, "start_file": ")" + (dir / "none.demo") + R"("}})",
             "demonstrations.start_file: " + (dir / "none.demo")},
            {head + R"("start_file": ")" + a + R"("}})", "demonstrations.start_file: has no effect without start_fraction above 0"},
            {R"({"algorithm": "bc", "env": {"name": "push"}, "demonstrations": {"file": ")" + a + R"(", "start_file": ")" + a +
                 R"("}})",
             "demonstrations.start_file: has no effect with \"algorithm\": \"bc\""}});
}

TEST_CASE("her: demonstrations.shift trains on moved demonstrations, the same run for the same seed, and misuse is one "
          "clear error each",
          "[cli][her][demos]") {
  ScratchDir dir("her_shift");
  train_on_changed_batches(dir, "shift", R"(, "shift": 0.05)");

  const std::string file = dir / "push.demo";
  rltest::check_config_errors(
      dir, {{R"({"algorithm": "sac", "env": {"name": "push", "control": "joints"}, "her": {}, "demonstrations": {"file": ")" + file +
                 R"(", "shift": 0.05}})",
             "demonstrations.shift: env \"push\" has no world positions to shift"},
            {R"({"algorithm": "ppo", "env": {"name": "push"}, "demonstrations": {"file": ")" + file + R"(", "shift": 0.05}})",
             "demonstrations.shift: has no effect with \"algorithm\": \"ppo\""},
            {R"({"algorithm": "sac", "env": {"name": "push"}, "demonstrations": {"file": ")" + file + R"(", "shift": 2}})",
             "demonstrations.shift"}});
}

TEST_CASE("her: demonstrations.start_redraw starts episodes in new layouts, the same run for the same seed, and misuse is "
          "one clear error each",
          "[cli][her][demos]") {
  ScratchDir dir("her_start_redraw");
  record_expert(dir, "push", 4);
  record_expert(dir, "reach", 4);
  const std::string starts = R"("file": "push.demo", "bc_epochs": 2, "start_fraction": 1)";
  train_plain_and_twice(dir, "redraw", starts, R"(, "start_redraw": 1)", 600);
  // The same demonstrated states, in other layouts: other episodes.
  CHECK(rltest::slurp(dir / "redraw1/episodes.csv") != rltest::slurp(dir / "plain/episodes.csv"));
  CHECK_THAT(rltest::slurp(dir / "redraw1/config.json"), Contains("\"start_redraw\": 1"));

  const std::string push = dir / "push.demo", reach = dir / "reach.demo";
  rltest::check_config_errors(
      dir, {{R"({"algorithm": "sac", "env": {"name": "reach"}, "demonstrations": {"file": ")" + reach +
                 R"(", "start_fraction": 0.5, "start_redraw": 1}})",
             "demonstrations.start_redraw: reach cannot draw its layout again mid-episode"},
            {R"({"algorithm": "sac", "env": {"name": "push"}, "her": {}, "demonstrations": {"file": ")" + push +
                 R"(", "start_redraw": 1}})",
             "demonstrations.start_redraw: has no effect without start_fraction above 0"},
            {R"({"algorithm": "bc", "env": {"name": "push"}, "demonstrations": {"file": ")" + push + R"(", "start_redraw": 1}})",
             "demonstrations.start_redraw: has no effect with \"algorithm\": \"bc\""},
            {R"({"algorithm": "sac", "env": {"name": "push"}, "her": {}, "demonstrations": {"file": ")" + push +
                 R"(", "start_fraction": 0.5, "start_redraw": 1.5}})",
             "demonstrations.start_redraw"}});
}

TEST_CASE("her: demonstrations.scatter trains on demonstrations with idle objects and goals moved, the same run for the "
          "same seed, and misuse is one clear error each",
          "[cli][her][demos]") {
  ScratchDir dir("her_scatter");
  // push's one cube is never idle: only the goal moves, before the cube does.
  train_on_changed_batches(dir, "scatter", R"(, "scatter": 1, "scatter_goal": true)");

  const std::string file = dir / "push.demo";
  rltest::check_config_errors(
      dir, {{R"({"algorithm": "sac", "env": {"name": "reach_goal"}, "her": {}, "demonstrations": {"file": ")" + file +
                 R"(", "scatter": 1}})",
             "demonstrations.scatter: env \"reach_goal\" has no objects to scatter"},
            {R"({"algorithm": "ppo", "env": {"name": "push"}, "demonstrations": {"file": ")" + file + R"(", "scatter": 1}})",
             "demonstrations.scatter: has no effect with \"algorithm\": \"ppo\""},
            {R"({"algorithm": "sac", "env": {"name": "push"}, "demonstrations": {"file": ")" + file + R"(", "scatter_goal": true}})",
             "demonstrations.scatter_goal: has no effect without scatter above 0"},
            {R"({"algorithm": "sac", "env": {"name": "push"}, "demonstrations": {"file": ")" + file + R"(", "scatter": 2}})",
             "demonstrations.scatter"}});
}
