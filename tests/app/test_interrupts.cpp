// Nothing lost on interrupt, one run per folder (training/interrupt.hpp, training/run_folder.hpp): the real
// binary is stopped by SIGINT, SIGTERM and SIGKILL at random moments and resumed; two runs are
// pointed at one folder.
#include <catch2/catch.hpp>

#include <filesystem>
#include <random>
#include <sys/resource.h>

#include "process_util.hpp"
#include "rdsim/training/model_file.hpp"
#include "rl_test_util.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace std::chrono_literals;

namespace {

// A CartPole PPO run of `total` steps with updates of 256 steps (anneal off: a resumed run with
// another total continues the same schedule), checkpoints every `seconds` of wall time.
std::string long_config(const rltest::ScratchDir& dir, const std::string& name, long long total, double seconds,
                        long long interval = 0, const std::string& env = R"({"name": "cartpole"})") {
  const std::string path = dir / (name + ".json");
  rltest::spit(path, R"({"env": )" + env + R"(, "seed": 11, "total_timesteps": )" + std::to_string(total) +
                         R"(, "num_envs": 4, "checkpoint_seconds": )" + std::to_string(seconds) +
                         R"(, "checkpoint_interval": )" + std::to_string(interval) + R"(,
      "network": {"hidden_sizes": [32, 32]},
      "ppo": {"n_steps": 64, "batch_size": 128, "n_epochs": 2, "learning_rate": 0.001}})");
  return path;
}

long long data_rows(const std::string& csv) {
  return static_cast<long long>(rltest::lines(rltest::slurp(csv)).size()) - 1;
}

// Polls until `path` has at least `rows` data rows (or the child ends).
void wait_rows(proctest::Child& c, const std::string& path, long long rows) {
  while (proctest::running(c) && (!fs::exists(path) || data_rows(path) < rows)) std::this_thread::sleep_for(2ms);
}

std::string weights(const std::string& model) { return rdsim::read_model_file(model).payload; }

bool same_logs(const std::string& a, const std::string& b) {
  return rltest::drop_columns(rltest::slurp(a + "/progress.csv"), 2) == rltest::drop_columns(rltest::slurp(b + "/progress.csv"), 2) &&
         rltest::drop_columns(rltest::slurp(a + "/episodes.csv"), 1) == rltest::drop_columns(rltest::slurp(b + "/episodes.csv"), 1);
}

}  // namespace

TEST_CASE("SIGINT saves checkpoint.bin and model.bin after the update in progress and exits 130, resuming loses nothing",
          "[interrupt]") {
  rltest::ScratchDir dir("sigint");
  const std::string config = long_config(dir, "c", 60000, 0.0);
  auto full = proctest::run({"train", "--quiet", "--config", config, "--log-dir", dir / "full"}, dir.path.string());
  REQUIRE(full.exit_code == 0);

  for (int sig : {SIGINT, SIGTERM}) {
    INFO("signal " << sig);
    const std::string run = dir / ("run" + std::to_string(sig));
    proctest::Child c = proctest::start({"train", "--quiet", "--config", config, "--log-dir", run}, dir / "out.txt", dir / "err.txt");
    wait_rows(c, run + "/progress.csv", 20 + sig);
    ::kill(c.pid, sig);
    const proctest::Outcome o = proctest::wait(c);
    REQUIRE(o.exit_code == 128 + sig);
    CHECK_THAT(o.err, Contains("continue with: rdsim train --resume " + run));
    // Nothing lost: the checkpoint covers every row the run wrote, and model.bin holds its weights.
    const long long rows = data_rows(run + "/progress.csv");
    const std::string resumed = rltest::slurp(run + "/progress.csv");
    const auto r = proctest::run({"train", "--quiet", "--resume", run}, dir.path.string());
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(rltest::lines(rltest::slurp(run + "/progress.csv")).size() > static_cast<size_t>(rows));
    CHECK(rltest::slurp(run + "/progress.csv").substr(0, resumed.size()) == resumed);  // no row dropped by the resume
    CHECK(same_logs(run, dir / "full"));
    CHECK(weights(run + "/model.bin") == weights(dir / "full/model.bin"));
  }
}

TEST_CASE("a second Ctrl-C exits at once, leaving the last complete checkpoint", "[interrupt]") {
  rltest::ScratchDir dir("sigint_twice");
  const std::string config = long_config(dir, "c", 100000, 0.0, 1024);
  const std::string run = dir / "run";
  proctest::Child c = proctest::start({"train", "--quiet", "--config", config, "--log-dir", run}, dir / "out.txt", dir / "err.txt");
  wait_rows(c, run + "/progress.csv", 10);
  ::kill(c.pid, SIGINT);
  // Two signals sent back to back may arrive as one: the second goes once the first is seen.
  while (proctest::running(c) && rltest::slurp(dir / "err.txt").find("stopping after this update") == std::string::npos)
    std::this_thread::sleep_for(1ms);
  ::kill(c.pid, SIGINT);
  const proctest::Outcome o = proctest::wait(c);
  CHECK(o.exit_code == 130);
  CHECK_THAT(o.err, Contains("interrupted again"));
  const auto r = proctest::run({"train", "--quiet", "--resume", run, "--timesteps", "20480"}, dir.path.string());
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(data_rows(run + "/progress.csv") == 20480 / 256);
}

TEST_CASE("SIGKILL at 20 random moments: every resume works and loses at most the checkpoint period", "[interrupt][kill]") {
  rltest::ScratchDir dir("sigkill");
  constexpr double period = 1.0;  // checkpoint_seconds for the test (default 60: the same code path)
  const std::string config = long_config(dir, "c", 100'000'000, period);
  const std::string run = dir / "run";
  std::mt19937 random(20240611);
  std::uniform_int_distribution<int> pause_ms(300, 2500);
  double worst_loss = 0.0;
  for (int kill = 0; kill < 20; ++kill) {
    INFO("kill " << kill);
    const std::vector<std::string> args =
        kill == 0 ? std::vector<std::string>{"train", "--quiet", "--config", config, "--log-dir", run}
                  : std::vector<std::string>{"train", "--quiet", "--resume", run};
    const auto started = fs::file_time_type::clock::now();
    proctest::Child c = proctest::start(args, dir / "out.txt", dir / "err.txt");
    while (kill == 0 && proctest::running(c) && !fs::exists(run + "/checkpoint.bin")) std::this_thread::sleep_for(2ms);
    std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(random)));
    REQUIRE(proctest::running(c));
    const auto killed_at = fs::file_time_type::clock::now();
    ::kill(c.pid, SIGKILL);
    proctest::wait(c);
    // Work lost = what this process did after its last checkpoint (or since it started, when it was
    // killed before its first one: the work of earlier processes was counted at their kills).
    REQUIRE(fs::exists(run + "/checkpoint.bin"));
    const auto saved = std::max(started, fs::last_write_time(run + "/checkpoint.bin"));
    const double lost = std::chrono::duration<double>(killed_at - saved).count();
    worst_loss = std::max(worst_loss, lost);
    CHECK(lost <= period + 2.0);  // the period, plus the update that was running (slack for a loaded machine)
    CHECK_NOTHROW(rdsim::read_model_file(run + "/checkpoint.bin"));
    CHECK_NOTHROW(rdsim::read_model_file(run + "/model.bin"));
  }
  WARN("worst work lost over 20 kills: " << worst_loss << " s (checkpoint_seconds " << period << ")");
  // Finish at a fixed total and compare with a run that was never killed.
  const long long rows = data_rows(run + "/progress.csv");
  const std::string total = std::to_string((rows + 40) * 256);
  auto r = proctest::run({"train", "--quiet", "--resume", run, "--timesteps", total}, dir.path.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  r = proctest::run({"train", "--quiet", "--config", config, "--timesteps", total, "--log-dir", dir / "full"}, dir.path.string());
  REQUIRE(r.exit_code == 0);
  CHECK(same_logs(run, dir / "full"));
  CHECK(weights(run + "/model.bin") == weights(dir / "full/model.bin"));
}

TEST_CASE("killed at a random update and resumed, every env's run is bit-identical to an uninterrupted one",
          "[interrupt][resume]") {
  rltest::ScratchDir dir("resume_envs");
  std::mt19937 random(7);
  // The shipped configs' env sections (random targets, the tasks' own numbers), small networks.
  const std::vector<std::pair<std::string, std::string>> envs = {
      {"cartpole", R"({"name": "cartpole"})"},
      {"jaka_button", R"({"name": "jaka_button", "random_target": true})"},
      {"jaka_obstacle", R"({"name": "jaka_obstacle", "random_target": true})"},
      {"inmoov_tomato", R"({"name": "inmoov_tomato", "random_target": true})"}};
  for (const auto& [name, env] : envs) {
    INFO(name);
    const long long total = 40 * 256;
    const std::string config = long_config(dir, name, total, 0.0, 256, env);  // a checkpoint after every update
    auto r = proctest::run({"train", "--quiet", "--config", config, "--log-dir", dir / (name + "_full")}, dir.path.string());
    REQUIRE(r.exit_code == 0);
    const std::string run = dir / (name + "_killed");
    proctest::Child c = proctest::start({"train", "--quiet", "--config", config, "--log-dir", run}, dir / "out.txt", dir / "err.txt");
    const long long at = std::uniform_int_distribution<long long>(3, 30)(random);
    wait_rows(c, run + "/progress.csv", at);
    const bool killed = proctest::running(c);
    ::kill(c.pid, SIGKILL);
    proctest::wait(c);
    INFO("killed after update " << at << (killed ? "" : " (the run had already ended)"));
    r = proctest::run({"train", "--quiet", "--resume", run}, dir.path.string());
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(same_logs(run, dir / (name + "_full")));
    CHECK(weights(run + "/model.bin") == weights(dir / (name + "_full/model.bin")));
  }
}

TEST_CASE("two runs on one folder: the second gets one clear error, the first completes intact", "[interrupt][concurrency]") {
  rltest::ScratchDir dir("two_runs");
  // Wide layers make each update slow enough for the second run to come while the first trains.
  const std::string config = dir / "c.json";
  rltest::spit(config, R"({"env": {"name": "cartpole"}, "seed": 4, "total_timesteps": 8192, "num_envs": 4,
      "network": {"hidden_sizes": [512, 512]}, "ppo": {"n_steps": 64, "batch_size": 64, "n_epochs": 8}})");
  const std::string run = dir / "run";
  proctest::Child first = proctest::start({"train", "--quiet", "--config", config, "--log-dir", run}, dir / "out1.txt", dir / "err1.txt");
  wait_rows(first, run + "/progress.csv", 1);
  REQUIRE(proctest::running(first));
  for (const std::vector<std::string>& args : {std::vector<std::string>{"train", "--quiet", "--config", config, "--log-dir", run},
                                               std::vector<std::string>{"train", "--quiet", "--config", config, "--log-dir", run, "--overwrite"},
                                               std::vector<std::string>{"train", "--quiet", "--resume", run}}) {
    const auto second = proctest::run(args, dir.path.string());
    CHECK(second.exit_code == 1);
    CHECK(rltest::lines(second.err).size() == 1);
    CHECK_THAT(second.err, Contains("rdsim: error: " + run + ": another rdsim run (pid " + std::to_string(first.pid) + ")"));
  }
  CHECK(proctest::running(first));  // the refusals came while it trained
  const proctest::Outcome o = proctest::wait(first);
  REQUIRE(o.exit_code == 0);
  // Intact: every update has its row, every finished episode its row, and the files load.
  const std::vector<std::string> progress = rltest::lines(rltest::slurp(run + "/progress.csv"));
  REQUIRE(progress.size() == 8192 / 256 + 1);
  const long long episodes = std::stoll(progress.back().substr(progress.back().find(',', progress.back().find(',') + 1) + 1));
  CHECK(data_rows(run + "/episodes.csv") == episodes);
  CHECK(proctest::run({"replay", run + "/model.bin", "-n", "1"}, dir.path.string()).exit_code == 0);
  CHECK(rdsim::read_model_file(run + "/checkpoint.bin").payload.substr(0, weights(run + "/model.bin").size()) ==
        weights(run + "/model.bin"));
}

TEST_CASE("a new run refuses a folder holding another run's files unless --resume or --overwrite", "[interrupt][concurrency]") {
  rltest::ScratchDir dir("folder_reuse");
  const std::string config = long_config(dir, "c", 1024, 60.0);
  const std::string run = dir / "run";
  REQUIRE(proctest::run({"train", "--quiet", "--config", config, "--log-dir", run}, dir.path.string()).exit_code == 0);
  const std::string before = rltest::slurp(run + "/model.bin");
  auto again = proctest::run({"train", "--quiet", "--config", config, "--log-dir", run, "--seed", "3"}, dir.path.string());
  CHECK(again.exit_code == 1);
  CHECK(rltest::lines(again.err).size() == 1);
  CHECK_THAT(again.err, Contains("holds the files of another run") && Contains("--resume " + run) && Contains("--overwrite"));
  CHECK(rltest::slurp(run + "/model.bin") == before);  // untouched
  // A leftover temporary of a killed writer does not count and is cleaned up.
  rltest::spit(run + "/.model.bin.AbC123.tmp", "half");
  again = proctest::run({"train", "--quiet", "--config", config, "--log-dir", run, "--seed", "3", "--overwrite"}, dir.path.string());
  INFO(again.err);
  CHECK(again.exit_code == 0);
  CHECK_FALSE(fs::exists(run + "/.model.bin.AbC123.tmp"));
  CHECK(rltest::slurp(run + "/model.bin") != before);
  CHECK_THAT(rltest::slurp(run + "/config.json"), Contains("\"seed\": 3"));
}

TEST_CASE("a run whose first checkpoint could not be written leaves a folder the message says how to reuse",
          "[interrupt][checkpoint]") {
  rltest::ScratchDir dir("first_checkpoint");
  const std::string config = long_config(dir, "c", 4096, 0.0, 256);
  const std::string run = dir / "run";
  // A file size limit of 8000 bytes: config.json and the first rows fit, checkpoint.bin does not
  // (what a nearly full disk does).
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    rlimit limit{8000, 8000};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(RDSIM_BINARY, RDSIM_BINARY, "train", "--quiet", "--config", config.c_str(), "--log-dir", run.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 1);
  REQUIRE_FALSE(std::filesystem::exists(run + "/checkpoint.bin"));
  // Before: the message said to continue with --resume, which then failed for want of a checkpoint.
  auto again = proctest::run({"train", "--quiet", "--config", config, "--log-dir", run}, dir.path.string());
  CHECK(again.exit_code == 1);
  CHECK_THAT(again.err, Contains("ended before its first checkpoint") && Contains("--overwrite"));
  CHECK_THAT(again.err, !Contains("--resume"));
  again = proctest::run({"train", "--quiet", "--config", config, "--log-dir", run, "--overwrite"}, dir.path.string());
  CHECK(again.exit_code == 0);
}
