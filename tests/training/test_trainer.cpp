// The Trainer as a library drives it (the Python package, tests): a config as JSON, start / update /
// finish, a stop asked for from outside, which saves and resumes exactly as Ctrl-C does.
#include <algorithm>
#include <catch2/catch.hpp>
#include <csignal>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/training/model_file.hpp"
#include "rdsim/training/trainer.hpp"
#include "../app/rl_test_util.hpp"

using Catch::Matchers::Contains;
using rdsim::Trainer;
using rdsim::TrainerSettings;

namespace {

// A short CartPole PPO run (anneal off, so a resumed run with a larger total matches), 512 steps per update.
nlohmann::json short_ppo(const std::string& log_dir) {
  nlohmann::json config = nlohmann::json::parse(R"({
    "algorithm": "ppo", "env": {"name": "cartpole"}, "seed": 3, "total_timesteps": 3072,
    "num_envs": 4, "checkpoint_interval": 0,
    "network": {"hidden_sizes": [32, 32]},
    "ppo": {"n_steps": 128, "batch_size": 128, "n_epochs": 2, "learning_rate": 0.001, "anneal_lr": false}
  })");
  config["log_dir"] = log_dir;
  return config;
}

TrainerSettings quiet_settings(const nlohmann::json& config) {
  TrainerSettings s;
  s.config = config;
  s.quiet = true;
  return s;
}

}  // namespace

TEST_CASE("a Trainer runs a config given as JSON and reports its run", "[trainer]") {
  rltest::ScratchDir dir("trainer_json");
  Trainer trainer(quiet_settings(short_ppo(dir / "run")));
  CHECK_FALSE(trainer.started());
  trainer.start();
  CHECK(trainer.config().env.name == "cartpole");
  CHECK(trainer.timesteps() == 0);
  int updates = 0;
  while (trainer.update()) ++updates;
  CHECK(updates + 1 == 6);  // 3072 steps, 512 per update: the last update returns false
  CHECK_FALSE(trainer.update());  // over: nothing more happens
  const rdsim::TrainResult r = trainer.finish();
  CHECK(r.exit_code == 0);
  CHECK(r.stop_signal == 0);
  CHECK(r.timesteps == 3072);
  CHECK(r.total_timesteps == 3072);
  CHECK(r.updates == 6);
  CHECK(r.episodes > 0);
  CHECK(r.stats.count > 0);
  CHECK(r.run_dir == dir / "run");
  CHECK(std::filesystem::exists(r.model_path));
  CHECK(std::filesystem::exists(r.checkpoint_path));
  CHECK(rltest::lines(rltest::slurp(dir / "run/progress.csv")).size() == 7);  // header + one row per update
  CHECK_FALSE(trainer.started());  // finish() released the run folder: another Trainer may take it
}

TEST_CASE("the Trainer's overrides and settings errors", "[trainer]") {
  rltest::ScratchDir dir("trainer_overrides");
  TrainerSettings s = quiet_settings(short_ppo(dir / "unused"));
  s.set_seed(5);
  s.set_timesteps(1024);
  s.set_log_dir(dir / "run");
  Trainer trainer(s);
  const rdsim::TrainResult r = trainer.run();
  CHECK(r.timesteps == 1024);
  CHECK(r.run_dir == dir / "run");
  CHECK_THAT(rltest::slurp(dir / "run/config.json"), Contains("\"seed\": 5"));

  TrainerSettings none;
  CHECK_THROWS_WITH(Trainer(none).start(), Contains("give a config"));
  TrainerSettings bad = quiet_settings(short_ppo(dir / "bad"));
  bad.config["total_timesteps"] = -1;
  CHECK_THROWS_WITH(Trainer(bad).start(), Contains("config: total_timesteps"));
}

TEST_CASE("request_stop saves a checkpoint from which a resumed Trainer matches an uninterrupted run", "[trainer]") {
  rltest::ScratchDir dir("trainer_stop");
  Trainer full(quiet_settings(short_ppo(dir / "full")));
  full.run();

  Trainer stopped(quiet_settings(short_ppo(dir / "part")));
  stopped.start();
  REQUIRE(stopped.update());
  stopped.request_stop(SIGINT);  // as from another thread or a host's signal handler
  CHECK_FALSE(stopped.update());
  const rdsim::TrainResult r = stopped.finish();
  CHECK(r.stop_signal == SIGINT);
  CHECK(r.exit_code == 130);
  CHECK(r.timesteps == 512);  // the update before the request, no more
  CHECK(std::filesystem::exists(r.checkpoint_path));

  TrainerSettings resume;
  resume.resume_dir = dir / "part";
  resume.quiet = true;
  const rdsim::TrainResult resumed = Trainer(resume).run();
  CHECK(resumed.exit_code == 0);
  CHECK(resumed.timesteps == 3072);
  CHECK(rltest::drop_columns(rltest::slurp(dir / "part/progress.csv"), 2) ==
        rltest::drop_columns(rltest::slurp(dir / "full/progress.csv"), 2));
  CHECK(rltest::drop_columns(rltest::slurp(dir / "part/episodes.csv"), 1) ==
        rltest::drop_columns(rltest::slurp(dir / "full/episodes.csv"), 1));
  CHECK((rdsim::read_model_file(dir / "part/model.bin").payload == rdsim::read_model_file(dir / "full/model.bin").payload));
}

TEST_CASE("a run on oneDNN's products gives the same CSVs on 1 and 2 threads and restores the backend", "[trainer]") {
  if (!rdsim::nn::onednn_available()) return;  // this build has only Eigen's products
  rltest::ScratchDir dir("trainer_onednn");
  const rdsim::nn::GemmBackend before = rdsim::nn::gemm_backend();
  const int threads_before = rdsim::nn::gemm_threads();
  for (const int threads : {1, 2}) {
    nlohmann::json config = short_ppo(dir / ("threads" + std::to_string(threads)));
    // Layers of 512: their products are cut into parts (nn/gemm.hpp) that 2 threads run side by side.
    config["network"]["hidden_sizes"] = {512, 512};
    config["ppo"]["batch_size"] = 256;
    config["gemm"] = "onednn";
    config["num_threads"] = threads;
    config["total_timesteps"] = 1024;
    Trainer trainer(quiet_settings(config));
    trainer.start();
    CHECK(rdsim::nn::gemm_backend() == rdsim::nn::GemmBackend::OneDnn);
    CHECK(rdsim::nn::gemm_threads() == threads);
    while (trainer.update()) {
    }
    trainer.finish();
  }
  CHECK(rdsim::nn::gemm_backend() == before);
  CHECK(rdsim::nn::gemm_threads() == threads_before);
  CHECK(rltest::drop_columns(rltest::slurp(dir / "threads1/progress.csv"), 2) ==
        rltest::drop_columns(rltest::slurp(dir / "threads2/progress.csv"), 2));
  CHECK(rltest::drop_columns(rltest::slurp(dir / "threads1/episodes.csv"), 1) ==
        rltest::drop_columns(rltest::slurp(dir / "threads2/episodes.csv"), 1));
  CHECK(rltest::slurp(dir / "threads1/config.json").find("\"gemm\": \"onednn\"") != std::string::npos);
}

TEST_CASE("a run with env_groups gives the same CSVs on 1 and 2 threads", "[trainer]") {
  rltest::ScratchDir dir("trainer_env_groups");
  for (const int threads : {1, 2}) {
    nlohmann::json config = short_ppo(dir / ("threads" + std::to_string(threads)));
    // A reach env (any worker may step it, so the groups overlap), episodes of 200 steps.
    config["env"] = {{"name", "jaka_button"}, {"is_discrete", true}};
    config["total_timesteps"] = 4096;
    config["env_groups"] = 2;  // rollouts act on one half of the envs while the workers step the other
    config["num_threads"] = threads;
    Trainer trainer(quiet_settings(config));
    trainer.start();
    while (trainer.update()) {
    }
    trainer.finish();
  }
  const std::string episodes = rltest::slurp(dir / "threads1/episodes.csv");
  CHECK(std::count(episodes.begin(), episodes.end(), '\n') > 15);
  CHECK(rltest::drop_columns(rltest::slurp(dir / "threads1/progress.csv"), 2) ==
        rltest::drop_columns(rltest::slurp(dir / "threads2/progress.csv"), 2));
  CHECK(rltest::drop_columns(episodes, 1) == rltest::drop_columns(rltest::slurp(dir / "threads2/episodes.csv"), 1));
}
