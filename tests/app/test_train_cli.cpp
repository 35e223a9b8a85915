// `rdsim train` and `rdsim replay` through the real binary, as a user runs them.
#include <catch2/catch.hpp>

#include "rdsim/training/model_file.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

// A short CartPole PPO config (anneal off, so a resumed run with a larger total matches).
std::string short_ppo(const ScratchDir& dir, long long interval = 0) {
  const std::string path = dir / "short_ppo.json";
  rltest::spit(path, R"({
    "algorithm": "ppo", "env": {"name": "cartpole"}, "seed": 3, "total_timesteps": 3072,
    "num_envs": 4, "checkpoint_interval": )" + std::to_string(interval) + R"(,
    "network": {"hidden_sizes": [32, 32]},
    "ppo": {"n_steps": 64, "batch_size": 128, "n_epochs": 4, "learning_rate": 0.001, "gamma": 0.98,
            "gae_lambda": 0.8}
  })");
  return path;
}

}  // namespace

TEST_CASE("train: a bad config exits non-zero with one clear message", "[cli]") {
  ScratchDir dir("cli_bad");
  const std::string bad = dir / "bad.json";
  rltest::spit(bad, R"({"env": {"name": "cartpole"}, "ppo": {"n_stepz": 8}})");
  auto r = run_rdsim("train --config " + bad + " --log-dir " + (dir / "run"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, StartsWith("rdsim: error: " + bad + ": ppo.n_stepz: unknown key"));

  r = run_rdsim("train --config " + (dir / "missing.json"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("missing.json"));

  rltest::spit(bad, R"({"env": {"name": "no_such_env"}})");
  r = run_rdsim("train --config " + bad + " --log-dir " + (dir / "run"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("no_such_env"));
  CHECK_THAT(r.err, Contains("cartpole"));
}

TEST_CASE("train: a relative config not found from the working folder is one rdsim carries (configs/)", "[cli]") {
  // An installed rdsim (the wheel) carries its configs: `rdsim train --config configs/X.json` works from
  // any folder. The folder searched is the data root ($RDSIM_ROOT here, else the source tree or the
  // data beside the installed binary).
  ScratchDir dir("cli_shipped_config");
  std::filesystem::create_directories(dir.path / "data/configs");
  std::filesystem::create_directories(dir.path / "work");
  std::filesystem::copy_file(short_ppo(dir), dir.path / "data/configs/carried.json");
  const std::string in_work = "cd " + (dir / "work") + " && RDSIM_ROOT=" + (dir / "data") + " " + RDSIM_BINARY;
  auto r = rltest::run_captured(in_work, "train --quiet --config configs/carried.json --log-dir run", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(std::filesystem::exists(dir.path / "work/run/model.bin"));  // the run folder stays relative to the working folder
  CHECK_THAT(rltest::slurp(dir / "work/run/config.json"), Contains("\"seed\": 3"));

  // A file of that name in the working folder comes first.
  std::filesystem::create_directories(dir.path / "work/configs");
  rltest::spit(dir / "work/configs/carried.json", R"({"env": {"name": "cartpole"}, "ppo": {"n_stepz": 8}})");
  r = rltest::run_captured(in_work, "train --quiet --config configs/carried.json --log-dir run2", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, StartsWith("rdsim: error: configs/carried.json: ppo.n_stepz: unknown key"));

  r = rltest::run_captured(in_work, "train --config configs/nowhere.json", dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("configs/nowhere.json"));
}

TEST_CASE("train: same config and seed give identical logs, the run folder has every file", "[cli]") {
  ScratchDir dir("cli_determinism");
  const std::string config = short_ppo(dir);
  for (const char* run : {"a", "b"}) {
    const auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / run), dir);
    REQUIRE(r.exit_code == 0);
    CHECK(rltest::lines(r.out).size() == 1);  // the summary, which --quiet keeps
    CHECK(r.err.empty());                     // no progress line
  }
  for (const char* file : {"progress.csv", "episodes.csv", "config.json", "model.bin", "checkpoint.bin"}) {
    CHECK(std::filesystem::exists(dir.path / "a" / file));
  }
  const std::string pa = rltest::slurp(dir / "a/progress.csv"), pb = rltest::slurp(dir / "b/progress.csv");
  CHECK(rltest::lines(pa).size() == 1 + 3072 / 256);
  CHECK(rltest::drop_columns(pa, 2) == rltest::drop_columns(pb, 2));  // all but steps_per_s, wall_time
  CHECK(rltest::drop_columns(rltest::slurp(dir / "a/episodes.csv"), 1) ==
        rltest::drop_columns(rltest::slurp(dir / "b/episodes.csv"), 1));
  // The weights are identical (the embedded configs differ in log_dir only).
  CHECK((rdsim::read_model_file(dir / "a/model.bin").payload == rdsim::read_model_file(dir / "b/model.bin").payload));

  const auto r = run_rdsim("train --quiet --config " + config + " --seed 4 --log-dir " + (dir / "c"), dir);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::drop_columns(rltest::slurp(dir / "c/progress.csv"), 2) != rltest::drop_columns(pa, 2));
  CHECK_THAT(rltest::slurp(dir / "c/config.json"), Contains("\"seed\": 4"));
}

TEST_CASE("train: the summary has success and the model, the rounding to whole rollouts is said", "[cli]") {
  ScratchDir dir("cli_summary");
  const std::string config = short_ppo(dir);  // rollouts of 64 steps x 4 envs
  auto r = run_rdsim("train --config " + config + " --timesteps 3000 --log-dir " + (dir / "run"), dir);
  REQUIRE(r.exit_code == 0);
  INFO(r.err);
  CHECK_THAT(r.err, Contains("rdsim train: total_timesteps 3000 rounds up to 3072: an update takes whole rollouts of 256 "
                             "steps (n_steps x num_envs)"));
  CHECK_THAT(r.err, Contains("3072/3072 steps (100%)"));
  CHECK(r.err.find("/3000") == std::string::npos);
  const auto out = rltest::lines(r.out);
  REQUIRE(out.size() == 1);
  CHECK_THAT(out[0], StartsWith("rdsim train: ppo on cartpole, 3072 timesteps (total_timesteps 3000 rounded up to whole "
                                "rollouts of 256 steps (n_steps x num_envs)), "));
  CHECK_THAT(out[0], Contains(" 93 episodes, last 93 episodes: success "));  // fewer than stats_window (100 by default)
  CHECK_THAT(out[0], Contains(", mean return "));
  CHECK_THAT(out[0], Contains(" s -> " + (dir / "run/model.bin")));
  // --quiet: the same summary, no progress line; a whole number of rollouts is not called rounded.
  r = run_rdsim("train --quiet --config " + config + " --timesteps 256 --log-dir " + (dir / "quiet"), dir);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  CHECK_THAT(r.out, StartsWith("rdsim train: ppo on cartpole, 256 timesteps, "));
  CHECK_THAT(r.out, Contains(" -> " + (dir / "quiet/model.bin")));
  // One update: its progress line is also the last, shown once.
  r = run_rdsim("train --config " + config + " --timesteps 256 --log-dir " + (dir / "one"), dir);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, StartsWith("256/256 steps (100%)"));
}

TEST_CASE("train --resume continues a run exactly like an uninterrupted one", "[cli]") {
  ScratchDir dir("cli_resume");
  const std::string config = short_ppo(dir, 1024);
  auto r = run_rdsim("train --quiet --config " + config + " --timesteps 6144 --log-dir " + (dir / "full"), dir);
  REQUIRE(r.exit_code == 0);
  r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "part"), dir);
  REQUIRE(r.exit_code == 0);
  // Rows written after the checkpoint (as by a crash) must not survive the resume.
  std::ofstream(dir / "part/progress.csv", std::ios::app) << "garbage\n";
  std::ofstream(dir / "part/episodes.csv", std::ios::app) << "garbage\n";
  r = run_rdsim("train --quiet --resume " + (dir / "part") + " --timesteps 6144", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::drop_columns(rltest::slurp(dir / "part/progress.csv"), 2) ==
        rltest::drop_columns(rltest::slurp(dir / "full/progress.csv"), 2));
  CHECK(rltest::drop_columns(rltest::slurp(dir / "part/episodes.csv"), 1) ==
        rltest::drop_columns(rltest::slurp(dir / "full/episodes.csv"), 1));
  CHECK((rdsim::read_model_file(dir / "part/model.bin").payload ==
         rdsim::read_model_file(dir / "full/model.bin").payload));

  r = run_rdsim("train --resume " + (dir / "nothing_here"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("nothing_here: no such run folder"));
}

TEST_CASE("train --resume of a finished run says it is complete, --timesteps extends it (first contact, item 8)", "[cli]") {
  ScratchDir dir("cli_resume_finished");
  const std::string config = short_ppo(dir, 1024);
  auto r = run_rdsim("train --quiet --config " + config + " --timesteps 2048 --log-dir " + (dir / "run"), dir);
  REQUIRE(r.exit_code == 0);
  const std::string progress = rltest::slurp(dir / "run/progress.csv");
  r = run_rdsim("train --resume " + (dir / "run"), dir);
  INFO(r.out << r.err);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("is already complete (2048 of 2048 steps); nothing to do") && Contains("--timesteps N (N > 2048)"));
  CHECK_THAT(r.out + r.err, !Contains("0 steps/s"));
  CHECK(rltest::slurp(dir / "run/progress.csv") == progress);
  r = run_rdsim("train --quiet --resume " + (dir / "run") + " --timesteps 4096", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("4096 timesteps"));
  CHECK(rltest::slurp(dir / "run/progress.csv").rfind(progress, 0) == 0);  // extended, the first rows kept
}

TEST_CASE("replay runs a model from the file alone, damaged files fail clearly", "[cli]") {
  ScratchDir dir("cli_replay");
  auto r = run_rdsim("train --quiet --config " + short_ppo(dir) + " --log-dir " + (dir / "run"), dir);
  REQUIRE(r.exit_code == 0);
  const std::string model = dir / "run/model.bin";
  r = run_rdsim("replay " + model + " -n 3", dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("episode 3: return"));
  CHECK_THAT(r.out, Contains("mean return"));
  const auto again = run_rdsim("replay " + model + " -n 3", dir);
  CHECK(again.out == r.out);  // deterministic actions, seeded env

  const std::string bytes = rltest::slurp(model);
  std::string damaged = bytes;
  damaged[bytes.size() / 2] = static_cast<char>(damaged[bytes.size() / 2] ^ 0x55);
  rltest::spit(dir / "damaged.bin", damaged);
  rltest::spit(dir / "truncated.bin", bytes.substr(0, bytes.size() / 2));
  rltest::spit(dir / "foreign.bin", "PK\x03\x04 this is a zip file");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"damaged.bin", "checksum mismatch"}, {"truncated.bin", "truncated"}, {"foreign.bin", "not an rdsim model"},
      {"absent.bin", "absent.bin"}};
  for (const auto& [file, why] : cases) {
    r = run_rdsim("replay " + (dir / file), dir);
    INFO(file << ": " << r.err);
    CHECK(r.exit_code == 1);
    CHECK(rltest::lines(r.err).size() == 1);
    CHECK_THAT(r.err, StartsWith("rdsim: error: " + (dir / file)));
    CHECK_THAT(r.err, Contains(why));
  }
}

TEST_CASE("PPO learns CartPole: mean return well above random within 30k steps", "[cli][learning]") {
  ScratchDir dir("cli_learning");
  const auto r = run_rdsim("train --quiet --config configs/cartpole_ppo.json --timesteps 30000 --log-dir " +
                               (dir / "run"),
                           dir);
  REQUIRE(r.exit_code == 0);
  const auto rows = rltest::lines(rltest::slurp(dir / "run/progress.csv"));
  REQUIRE(rows.size() > 2);
  // mean_return, the 4th column, is the mean of the last 20 episodes (random play: about 22).
  double mean_return = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    std::string cell = rows[i];
    for (int k = 0; k < 3; ++k) cell = cell.substr(cell.find(',') + 1);
    cell = cell.substr(0, cell.find(','));
    if (!cell.empty()) mean_return = std::max(mean_return, std::stod(cell));
  }
  INFO("best mean return of 20 consecutive episodes within 30k steps: " << mean_return);
  CHECK(mean_return > 150.0);
}
