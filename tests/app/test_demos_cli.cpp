// `rdsim demos`, the scripted expert, and learning from demonstrations through the real binary.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/envs/registry.hpp"
#include "process_util.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

// "success rate 0.87" from `rdsim replay`'s last line.
double replay_success(const std::string& out) {
  const auto at = out.rfind("success rate ");
  REQUIRE(at != std::string::npos);
  return std::stod(out.substr(at + 13));
}

// Success rate of uniformly random actions over `episodes` episodes from reset(seed), then continued resets.
double random_success(const std::string& env_name, std::uint64_t seed, int episodes) {
  rdsim::EnvConfig c = rdsim::default_env_config(env_name);
  c.get<rdsim::ReachOptions>().random_target = true;
  auto env = rdsim::make_env(c);
  rdsim::Rng rng(seed);
  int successes = 0;
  for (int k = 0; k < episodes; ++k) {
    env->reset(k == 0 ? std::optional<std::uint64_t>(seed) : std::nullopt);
    for (bool done = false; !done;) {
      const rdsim::StepResult r = env->step(rdsim::Action::discrete(static_cast<int>(rng.below(6))));
      successes += r.info.success;
      done = r.terminated || r.truncated;
    }
  }
  return static_cast<double>(successes) / episodes;
}

std::string bc_config(const std::string& env_name, const std::string& demos, bool discrete = true) {
  nlohmann::json c = {{"algorithm", "bc"},
                      {"env", {{"name", env_name}, {"random_target", true}, {"is_discrete", discrete}}},
                      {"seed", 1},
                      {"total_timesteps", 512},
                      {"num_envs", 2},
                      {"network", {{"hidden_sizes", {64, 64}}, {"input_scale", 10.0}}},
                      {"bc", {{"n_steps", 256}}},
                      {"demonstrations", {{"file", demos}, {"bc_epochs", 200}, {"patience", 20}}}};
  return c.dump(2);
}

}  // namespace

TEST_CASE("behaviour cloning on a few expert episodes beats random actions by far on unseen seeds", "[demos][bc]") {
  ScratchDir dir("demos_bc");
  const std::string demos = dir / "button.demo";
  auto r = run_rdsim("demos record --expert --env jaka_button -n 10 --seed 100 -q --out " + demos, dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("wrote 10 scripted episodes"));

  r = run_rdsim("demos info " + demos, dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("episodes     10 (10 scripted, 0 human)"));
  CHECK_THAT(r.out, Contains("success rate 1.00"));
  CHECK_THAT(r.out, Contains("actions Discrete(6)"));

  rltest::spit(dir / "bc.json", bc_config("jaka_button", demos));
  r = run_rdsim("train --quiet --config " + (dir / "bc.json") + " --log-dir " + (dir / "run"), dir);
  REQUIRE(r.exit_code == 0);
  const auto pretrain = rltest::lines(rltest::slurp(dir / "run/pretrain.csv"));
  REQUIRE(pretrain.size() > 2);
  CHECK(pretrain[0] == "epoch,actor_loss,actor_val_loss,actor_val_error");

  // Held-out seeds: the demonstrations started from reset(100..109); these from reset(7000) on.
  r = run_rdsim("replay " + (dir / "run/model.bin") + " -n 50 --seed 7000", dir);
  REQUIRE(r.exit_code == 0);
  const double cloned = replay_success(r.out), random = random_success("jaka_button", 7000, 50);
  INFO("behaviour cloning " << cloned << ", random actions " << random);
  CHECK(cloned >= 0.8);
  CHECK(cloned >= random + 0.6);
}

TEST_CASE("the scripted expert's file replays: its actions from its seeds give its observations", "[demos]") {
  ScratchDir dir("demos_replay");
  const std::string demos = dir / "obstacle.demo";
  REQUIRE(run_rdsim("demos record --expert --env jaka_obstacle -n 3 -q --out " + demos, dir).exit_code == 0);
  const rdsim::DemoFile f = rdsim::read_demo_file(demos);
  REQUIRE(f.episodes.size() == 3);
  for (const rdsim::DemoEpisode& e : f.episodes) {
    CHECK(e.source == rdsim::DemoSource::Scripted);
    rdsim::ConfigReader reader(e.env_config, demos, "env");
    auto env = rdsim::make_env(rdsim::read_env_config(reader));
    REQUIRE(e.seed);
    CHECK(env->reset(*e.seed).values == e.observations[0].values);
    for (int t = 0; t < e.steps(); ++t) {
      const rdsim::StepResult s = env->step(e.actions[static_cast<size_t>(t)]);
      REQUIRE(s.observation.values == e.observations[static_cast<size_t>(t) + 1].values);
      CHECK(s.reward == e.rewards[static_cast<size_t>(t)]);
    }
    CHECK(e.success());  // the expert goes round the column
  }
}

TEST_CASE("demos record --action-noise: the actions taken, noisy, replay to the file's observations, the same twice",
          "[demos]") {
  ScratchDir dir("demos_noise");
  const std::string args = "demos record --expert --env jaka_button --continuous -n 3 -q --seed 7 --out ";
  REQUIRE(run_rdsim(args + (dir / "clean.demo"), dir).exit_code == 0);
  REQUIRE(run_rdsim(args + (dir / "a.demo") + " --action-noise 0.2", dir).exit_code == 0);
  REQUIRE(run_rdsim(args + (dir / "b.demo") + " --action-noise 0.2", dir).exit_code == 0);
  const rdsim::DemoFile clean = rdsim::read_demo_file(dir / "clean.demo"), noisy = rdsim::read_demo_file(dir / "a.demo");
  CHECK(noisy.episodes.size() == 3);
  // Each episode's noise comes from its seed: the same command writes the same episodes.
  const rdsim::DemoFile again = rdsim::read_demo_file(dir / "b.demo");
  for (std::size_t k = 0; k < noisy.episodes.size(); ++k) CHECK(noisy.episodes[k].actions.size() == again.episodes[k].actions.size());
  CHECK(noisy.episodes[0].actions[0].values == again.episodes[0].actions[0].values);
  // The first action differs from the expert's own, and the file holds what was taken: it replays.
  CHECK(noisy.episodes[0].actions[0].values != clean.episodes[0].actions[0].values);
  const rdsim::DemoEpisode& e = noisy.episodes[0];
  rdsim::ConfigReader reader(e.env_config, dir / "a.demo", "env");
  auto env = rdsim::make_env(rdsim::read_env_config(reader));
  REQUIRE(env->reset(*e.seed).values == e.observations[0].values);
  for (int t = 0; t < e.steps(); ++t) {
    const auto i = static_cast<std::size_t>(t);
    CHECK(e.actions[i].values.cwiseAbs().maxCoeff() <= 1.0f);  // clipped to the Box
    REQUIRE(env->step(e.actions[i]).observation.values == e.observations[i + 1].values);
  }
  // Discrete actions take no noise.
  auto r = run_rdsim("demos record --expert --env jaka_button -n 1 -q --action-noise 0.1 --out " + (dir / "d.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("demos record: --action-noise: expected Box actions (jaka_button has Discrete ones)"));
  // Nor does a noise that is not a number, and nothing is written.
  r = run_rdsim("demos record --expert --env push -n 1 -q --action-noise nan --out " + (dir / "n.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("demos record: --action-noise: expected a standard deviation from 0 to 10, got nan"));
  CHECK_FALSE(std::filesystem::exists(dir / "n.demo"));
}

TEST_CASE("demos record --missed-grasps: longer episodes that still succeed and replay, one clear error where nothing is grasped",
          "[demos]") {
  ScratchDir dir("demos_missed");
  const std::string args = "demos record --expert --env pick_and_place -n 3 -q --seed 5 --out ";
  REQUIRE(run_rdsim(args + (dir / "clean.demo"), dir).exit_code == 0);
  REQUIRE(run_rdsim(args + (dir / "missed.demo") + " --missed-grasps 1", dir).exit_code == 0);
  const rdsim::DemoFile clean = rdsim::read_demo_file(dir / "clean.demo"), missed = rdsim::read_demo_file(dir / "missed.demo");
  REQUIRE(missed.episodes.size() == 3);
  for (std::size_t k = 0; k < missed.episodes.size(); ++k) {
    INFO("episode " << k);
    CHECK(missed.episodes[k].success());
    // Down beside the cube, shut, up and over again: longer than the expert's own episode.
    CHECK(missed.episodes[k].steps() > clean.episodes[k].steps() + 5);
  }
  const rdsim::DemoEpisode& e = missed.episodes[0];
  rdsim::ConfigReader reader(e.env_config, dir / "missed.demo", "env");
  auto env = rdsim::make_env(rdsim::read_env_config(reader));
  REQUIRE(env->reset(*e.seed).values == e.observations[0].values);
  for (int t = 0; t < e.steps(); ++t)
    REQUIRE(env->step(e.actions[static_cast<std::size_t>(t)]).observation.values == e.observations[static_cast<std::size_t>(t) + 1].values);

  auto r = run_rdsim("demos record --expert --env push -n 1 -q --missed-grasps 0.5 --out " + (dir / "p.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("demos record: --missed-grasps: expected a task that grasps a cube (pick_and_place, stack), got push"));
  CHECK_FALSE(std::filesystem::exists(dir / "p.demo"));
  r = run_rdsim("demos record --expert --env stack -n 1 -q --missed-grasps nan --out " + (dir / "n.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("demos record: --missed-grasps: expected a share of the episodes from 0 to 1, got nan"));
}

TEST_CASE("bad demonstration files and demonstrations of another env are one clear error", "[demos][bad-file]") {
  ScratchDir dir("demos_bad");
  const std::string demos = dir / "button.demo";
  REQUIRE(run_rdsim("demos record --expert --env jaka_button -n 2 -q --out " + demos, dir).exit_code == 0);
  const std::string bytes = rdsim::read_file(demos);

  rltest::spit(dir / "cut.demo", bytes.substr(0, bytes.size() - 100));
  auto r = run_rdsim("demos info " + (dir / "cut.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("cut.demo: file is truncated"));

  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x04;
  rltest::spit(dir / "flip.demo", flipped);
  r = run_rdsim("demos info " + (dir / "flip.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("flip.demo: episode"));
  CHECK_THAT(r.err, Contains("file is damaged (checksum mismatch)"));

  // Training on them with another env, or another action space.
  rltest::spit(dir / "obstacle.json", bc_config("jaka_obstacle", demos));
  r = run_rdsim("train --quiet --config " + (dir / "obstacle.json") + " --log-dir " + (dir / "run1"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, Contains("button.demo: these demonstrations do not fit the env: recorded on env jaka_button, "
                             "this env is jaka_obstacle"));
  rltest::spit(dir / "box.json", bc_config("jaka_button", demos, false));
  r = run_rdsim("train --quiet --config " + (dir / "box.json") + " --log-dir " + (dir / "run2"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("actions are Discrete(6), env jaka_button has Box(3) (env.is_discrete differs)"));
  // A truncated file stops training the same way.
  rltest::spit(dir / "cut.json", bc_config("jaka_button", dir / "cut.demo"));
  r = run_rdsim("train --quiet --config " + (dir / "cut.json") + " --log-dir " + (dir / "run3"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("file is truncated"));

  // Recording into an existing file needs --append; appending another env is refused.
  r = run_rdsim("demos record --expert --env jaka_button -n 1 -q --out " + demos, dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("already exists"));
  r = run_rdsim("demos record --expert --env jaka_obstacle -n 1 -q --append --out " + demos, dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("cannot append: recorded on env jaka_button"));
  r = run_rdsim("demos record --expert --env cartpole -n 1 -q --out " + (dir / "cp.demo"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("env cartpole has no scripted expert"));
}

TEST_CASE("demonstrations in training configs: checked keys", "[demos][config]") {
  const auto parse = [](const nlohmann::json& j) { return rdsim::parse_train_config(j, "cfg.json", "cfg"); };
  nlohmann::json c = {{"algorithm", "bc"}, {"env", {{"name", "jaka_button"}}}};
  CHECK_THROWS_WITH(parse(c), Contains("cfg.json: demonstrations: missing: bc learns from demonstrations"));
  c["demonstrations"] = {{"file", "x.demo"}, {"fit_critic", true}};
  CHECK_THROWS_WITH(parse(c), Contains("demonstrations.fit_critic: has no effect with \"algorithm\": \"bc\""));
  c["algorithm"] = "ppo";
  c["demonstrations"] = {{"file", "x.demo"}, {"large_margin", true}};
  CHECK_THROWS_WITH(parse(c), Contains("demonstrations.large_margin: has no effect with \"algorithm\": \"ppo\""));
  c["algorithm"] = "dqn";
  c["demonstrations"] = {{"file", "x.demo"}, {"bc_weight", 0.5}};
  CHECK_THROWS_WITH(parse(c), Contains("demonstrations.bc_weight: has no effect with \"algorithm\": \"dqn\""));
  c["algorithm"] = "ppo";
  c["demonstrations"] = {{"bc_epochs", 3}};
  CHECK_THROWS_WITH(parse(c), Contains("demonstrations.file"));
  c["demonstrations"] = {{"file", "x.demo"}, {"bc_epochs", 3}};
  const rdsim::TrainConfig t = parse(c);
  REQUIRE(t.algorithm.demonstrations);
  CHECK(t.algorithm.demonstrations->bc_epochs == 3);
  // The resolved config keeps them (config.json, model.bin).
  CHECK(rdsim::to_json(t)["demonstrations"]["file"] == "x.demo");
  CHECK(parse(rdsim::to_json(t)).algorithm.demonstrations->bc_epochs == 3);
}

namespace {

// `demos record` started through stdbuf -oL (a terminal's line buffering, which users see), stdout
// and stderr in files.
proctest::Child start_recording(const std::string& args, const std::string& dir, const std::string& tag) {
  proctest::Child c{-1, dir + "/" + tag + ".out", dir + "/" + tag + ".err", false, 0};
  c.pid = ::fork();
  if (c.pid == 0) {
    const int out = ::open(c.out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(c.err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<std::string> argv_s = {"stdbuf", "-oL", RDSIM_BINARY};
    for (auto& a : proctest::split_args(args)) argv_s.push_back(a);
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execvp("stdbuf", argv.data());
    ::_exit(127);
  }
  return c;
}

long long count_lines(const std::string& text, const std::string& prefix) {
  long long n = 0;
  for (std::size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("demos record: kill -9 loses no episode reported as written", "[demos][crash]") {
  ScratchDir dir("demos_kill9");
  for (int trial = 0; trial < 5; ++trial) {
    // Built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + std::to_string(...).
    std::string tag = "k";
    tag += std::to_string(trial);
    const std::string demos = (dir.path / (tag + ".demo")).string();
    std::string args = "demos record --expert --env jaka_button -n 1000 --seed ";
    args += std::to_string(10 * trial);
    args += " --out ";
    args += demos;
    proctest::Child c = start_recording(args, dir.path.string(), tag);  // a fresh log each
    // Kill it the moment a line reports another episode.
    const long long wanted = 2 + trial;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (proctest::running(c) && count_lines(rltest::slurp(c.out_path), "episode (seed") < wanted &&
           std::chrono::steady_clock::now() < deadline) {
    }
    ::kill(c.pid, SIGKILL);
    proctest::wait(c);
    const long long reported = count_lines(rltest::slurp(c.out_path), "episode (seed");
    REQUIRE(reported >= wanted);
    // Before: the line came before the episode was written and synced: the last one was missing.
    CHECK(static_cast<long long>(rdsim::read_demo_file(demos).episodes.size()) >= reported);
  }
}

TEST_CASE("demos record: two recordings into one file at once, the second is refused and nothing is lost",
          "[demos][lock]") {
  ScratchDir dir("demos_two_writers");
  const std::string demos = (dir.path / "c.demo").string();
  REQUIRE(run_rdsim("demos record --expert --env jaka_button -n 1 -q --out " + demos, dir).exit_code == 0);
  proctest::Child a = start_recording("demos record --expert --env jaka_button -n 30 -q --append --seed 1 --out " + demos,
                                      dir.path.string(), "a");
  proctest::Child b = start_recording("demos record --expert --env jaka_button -n 30 -q --append --seed 2 --out " + demos,
                                      dir.path.string(), "b");
  const proctest::Outcome ra = proctest::wait(a), rb = proctest::wait(b);
  int ok = 0;
  for (const proctest::Outcome* r : {&ra, &rb}) {
    if (r->exit_code == 0) {
      ++ok;
    } else {
      CHECK(r->exit_code == 1);
      CHECK_THAT(r->err, Contains("another rdsim process is recording to this demonstration file"));
    }
  }
  CHECK(ok >= 1);
  // Before: both exited 0, both said "which holds 31", and the file was damaged.
  const rdsim::DemoFile f = rdsim::read_demo_file(demos);
  CHECK(static_cast<int>(f.episodes.size()) == 1 + 30 * ok);
}

TEST_CASE("a FIFO or a device as a demonstration file is refused at once by every command", "[demos][bad-file]") {
  ScratchDir dir("demos_fifo");
  const std::string fifo = (dir.path / "x.fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string config = (dir.path / "bc.json").string();
  rltest::spit(config, bc_config("jaka_button", fifo));
  // Before: each of these waited for a FIFO writer for ever, and /dev/urandom was read on and on.
  const std::vector<std::vector<std::string>> commands = {
      {"demos", "info", fifo},
      {"demos", "info", "/dev/urandom"},
      {"demos", "record", "--expert", "--env", "jaka_button", "-n", "1", "-q", "--append", "--out", fifo},
      {"train", "--quiet", "--config", config, "--log-dir", (dir.path / "run").string()}};
  for (const auto& args : commands) {
    INFO(args[0] << " " << args[1] << " " << args.back());
    const proctest::Outcome r = proctest::run(args, dir.path.string(), 0, std::chrono::seconds(60));
    CHECK_FALSE(r.timed_out);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("is not a regular file"));
  }
}

TEST_CASE("train: a config's paths are relative to its folder, and a missing demonstration file names key and config "
          "(first contact, item 3)",
          "[cli][demos]") {
  ScratchDir dir("cli_config_paths");
  const std::filesystem::path sub = dir.path / "experiments";
  std::filesystem::create_directories(sub / "demos");
  auto r = run_rdsim("demos record --quiet --expert --env jaka_obstacle -n 2 --out " + (sub / "demos/obstacle.demo").string(), dir);
  REQUIRE(r.exit_code == 0);
  const auto config = [&](const std::string& file) {
    rltest::spit((sub / "bc.json").string(), R"({"algorithm": "bc", "env": {"name": "jaka_obstacle"}, "total_timesteps": 64,
      "log_dir": "runs/bc", "bc": {"n_steps": 64}, "demonstrations": {"file": ")" + file + R"(", "bc_epochs": 2}})");
    return (sub / "bc.json").string();
  };
  // Run from `dir`, not the config's folder: demos/... and runs/... are found and made beside the config.
  const auto in_dir = [&](const std::string& args) { return rltest::run_captured("cd " + dir.path.string() + " && " + RDSIM_BINARY, args, dir); };
  r = in_dir("train --quiet --config " + config("demos/obstacle.demo"));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(std::filesystem::exists(sub / "runs/bc/model.bin"));
  const auto recorded = nlohmann::json::parse(rltest::slurp((sub / "runs/bc/config.json").string()));
  CHECK(recorded["demonstrations"]["file"] == (sub / "demos/obstacle.demo").lexically_normal().string());
  // A path on the command line is relative to the current folder.
  r = in_dir("train --quiet --config " + config("demos/obstacle.demo") + " --log-dir cli_run");
  CHECK(r.exit_code == 0);
  CHECK(std::filesystem::exists(dir.path / "cli_run/model.bin"));
  // A missing file: the config, the key and the folder searched.
  r = in_dir("train --quiet --config " + config("demos/missing.demo") + " --overwrite");
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains(sub.string() + "/bc.json: demonstrations.file: " + (sub / "demos/missing.demo").string()));
}
