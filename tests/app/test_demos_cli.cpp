// `rdsim demos`, the scripted expert, and learning from demonstrations through the real binary.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "rdsim/training/train_config.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/envs/registry.hpp"
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
  c.random_target = true;
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
