#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "rdsim/training/memory_check.hpp"
#include "rdsim/training/run_folder.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "../error_of.hpp"
#include "../app/rl_test_util.hpp"

using Catch::Matchers::Contains;

namespace {

// Writes `text` as <dir>/<name>.json and reads it; returns the error message ("" when none).
std::string config_error(const rltest::ScratchDir& dir, const std::string& text) {
  const std::string path = dir / "bad.json";
  rltest::spit(path, text);
  try {
    rdsim::read_train_config(path);
  } catch (const rdsim::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the shipped CartPole configs parse with the documented values", "[train_config]") {
  const auto ppo = rdsim::read_train_config("configs/cartpole_ppo.json");
  CHECK(ppo.algorithm.name() == "ppo");
  CHECK(ppo.env.name == "cartpole");
  CHECK(ppo.name == "cartpole_ppo");
  CHECK(ppo.log_dir == "runs/cartpole_ppo");
  CHECK(ppo.num_envs == 8);
  CHECK(std::get<rdsim::PpoConfig>(ppo.algorithm.params).n_steps == 32);
  CHECK(std::get<rdsim::PpoConfig>(ppo.algorithm.params).gae_lambda == 0.8);
  CHECK(ppo.algorithm.network.hidden_sizes == std::vector<int>{64, 64});
  const auto a2c = rdsim::read_train_config("configs/cartpole_a2c.json");
  CHECK(a2c.algorithm.name() == "a2c");
  CHECK(std::get<rdsim::A2cConfig>(a2c.algorithm.params).optimizer == "rmsprop");
  CHECK(std::get<rdsim::A2cConfig>(a2c.algorithm.params).learning_rate == 7e-4);
  const auto dqn = rdsim::read_train_config("configs/cartpole_dqn.json");
  CHECK(dqn.algorithm.name() == "dqn");
}

TEST_CASE("every shipped config parses, and its resolved form reads back to itself", "[train_config]") {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator("configs")) {
    if (entry.path().extension() != ".json") continue;
    INFO(entry.path());
    const auto c = rdsim::read_train_config(entry.path().string());
    const nlohmann::json j = rdsim::to_json(c);
    CHECK(rdsim::to_json(rdsim::parse_train_config(j, "resolved", c.name)) == j);
    ++count;
  }
  CHECK(count >= 20);
  const auto ddpg = rdsim::read_train_config("configs/pendulum_ddpg.json");
  CHECK(ddpg.algorithm.name() == "ddpg");
  CHECK_FALSE(std::get<rdsim::DdpgConfig>(ddpg.algorithm.params).twin_q);  // DDPG's defaults, not TD3's
  CHECK(ddpg.env.max_steps == 200);
}

TEST_CASE("the resolved config has every default and reads back to itself", "[train_config]") {
  rltest::ScratchDir dir("config_roundtrip");
  rltest::spit(dir / "tiny.json", R"({"env": {"name": "cartpole"}})");
  const auto c = rdsim::read_train_config(dir / "tiny.json");
  CHECK(c.algorithm.name() == "ppo");
  CHECK(c.log_dir == "runs/tiny");
  CHECK(std::get<rdsim::PpoConfig>(c.algorithm.params).n_steps == 2048);
  const nlohmann::json j = rdsim::to_json(c);
  CHECK(j.at("ppo").at("clip_range") == 0.2);
  CHECK(j.at("network").at("activation") == "tanh");
  CHECK_FALSE(j.contains("a2c"));
  const auto back = rdsim::parse_train_config(j, "resolved", "tiny");
  CHECK(rdsim::to_json(back) == j);
}

TEST_CASE("config errors name the file and the key", "[train_config]") {
  rltest::ScratchDir dir("config_errors");
  const std::string file = dir / "bad.json";
  auto check = [&](const std::string& text, const std::string& key) {
    const std::string msg = config_error(dir, text);
    INFO(text << " -> " << msg);
    CHECK_THAT(msg, Contains(file));
    CHECK_THAT(msg, Contains(key));
  };
  check(R"({"env": {"name": "cartpole"}, "bogus": 1})", "bogus: unknown key");
  check(R"({"env": {"name": "cartpole"}, "ppo": {"clip": 0.2}})", "ppo.clip: unknown key");
  check(R"({"env": {"name": "cartpole", "colour": "red"}})", "env.colour: unknown key");
  check(R"({"env": {"name": "cartpole"}, "num_envs": "eight"})", "num_envs: expected an integer");
  check(R"({"env": {"name": "cartpole"}, "network": {"shared": 1}})", "network.shared: expected true or false");
  check(R"({"env": {"name": "cartpole"}, "ppo": {"gamma": 1.5}})", "ppo.gamma: expected a number in [0, 1]");
  check(R"({"env": {"name": "cartpole"}, "total_timesteps": 0})", "total_timesteps");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "a2c", "a2c": {"optimizer": "sgd"}})", "a2c.optimizer");
  check(R"({"env": {"name": "cartpole"}, "a2c": {"optimizer": "adam"}})", "a2c: has no effect with \"algorithm\": \"ppo\"");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "sax"})", "algorithm: expected one of");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "ddpg", "td3": {"tau": 0.1}})", "td3: has no effect with \"algorithm\": \"ddpg\"");
  check(R"({"env": {"name": "pendulum"}, "algorithm": "td3", "td3": {"action_noise": "pink"}})", "td3.action_noise");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "ars", "ars": {"n_delta": 4, "n_top": 5}})", "ars.n_top: expected at most n_delta");
  check(R"({"seed": 1})", "env: missing");
  check(R"({"env": {"name": "cartpole"}, "network": {"hidden_sizes": [64, -1]}})", "network.hidden_sizes");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "dqn", "dqn": {"batch_size": 0}})", "dqn.batch_size");
  check(R"({"env": {"name": "cartpole"}, "network": {"input_scale": 0}})", "network.input_scale");
  check(R"({"env": {"name": "jaka_button", "observation": "raw_pixels"}, "network": {"input_scale": 10}})",
        "network.input_scale: only for vector observations");
  check(R"({"env": {"name": "cartpole"}, "seed": 1,})", "not valid JSON");
  check(R"([1, 2])", "expected a JSON object");
}

TEST_CASE("a missing config file is an error naming it", "[train_config]") {
  try {
    rdsim::read_train_config("configs/does_not_exist.json");
    FAIL("no error");
  } catch (const rdsim::Error& e) {
    CHECK_THAT(e.what(), Contains("configs/does_not_exist.json"));
  }
}

TEST_CASE("command-line overrides are read by the config file's rules, naming the option", "[train_config][cli]") {
  nlohmann::json j = {{"env", {{"name", "cartpole"}}}, {"seed", 1}};
  const auto error = [&](std::vector<rdsim::ConfigOverride> o) {
    nlohmann::json copy = j;
    try {
      rdsim::apply_overrides(copy, o, "c.json");
    } catch (const rdsim::Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK_THAT(error({{"--seed", "seed", "-1"}}), Contains("--seed: seed: expected an integer in [0, 2^64 - 1], got -1"));
  CHECK_THAT(error({{"--timesteps", "total_timesteps", "1e18"}}), Contains("--timesteps: total_timesteps") && Contains("[1, 1e12]"));
  CHECK_THAT(error({{"--log-dir", "log_dir", ""}}), Contains("--log-dir: expected a value"));
  nlohmann::json ok = j;
  rdsim::apply_overrides(ok, {{"--seed", "seed", "7"}, {"--timesteps", "total_timesteps", "1e4"}}, "c.json");
  const auto c = rdsim::parse_train_config(ok, "c.json", "c");
  CHECK(c.seed == 7);
  CHECK(c.total_timesteps == 10000);
  // The value the override replaces must be valid too.
  j["seed"] = -3;
  CHECK_THAT(error({{"--seed", "seed", "7"}}), Contains("c.json: seed: expected an integer"));
}

TEST_CASE("keys without effect and contradicting keys are errors naming why", "[train_config]") {
  rltest::ScratchDir dir("config_rules");
  auto check = [&](const std::string& text, const std::string& why) {
    const std::string msg = config_error(dir, text);
    INFO(text << " -> " << msg);
    CHECK_THAT(msg, Contains(why));
  };
  check(R"({"env": {"name": "cartpole"}, "ppo": {"n_steps": 16, "batch_size": 64}})", "ppo.batch_size: expected at most the rollout size");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "dqn", "dqn": {"exploration_initial_eps": 0.1, "exploration_final_eps": 0.5}})",
        "dqn.exploration_final_eps: expected at most exploration_initial_eps");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "dqn", "total_timesteps": 50})", "dqn.learning_starts: expected fewer than total_timesteps");
  check(R"({"env": {"name": "pendulum"}, "algorithm": "sac", "total_timesteps": 50})", "sac.learning_starts: expected fewer than total_timesteps");
  check(R"({"env": {"name": "pendulum"}, "algorithm": "td3", "td3": {"buffer_size": 100, "batch_size": 256}})",
        "td3.batch_size: expected at most buffer_size");
  check(R"({"env": {"name": "jaka_button", "multi_view": true}})", "env.multi_view: has no effect without");
  check(R"({"env": {"name": "jaka_button", "image_width": 128}})", "env.image_width: has no effect without");
  check(R"({"env": {"name": "jaka_button", "image_channels": "rgb_depth"}})", "env.image_channels: has no effect without");
  check(R"({"env": {"name": "jaka_button", "observation": "raw_pixels", "image_channels": "rgbd"}})", "env.image_channels");
  check(R"({"env": {"name": "cartpole", "urdf_root": "x"}})", "env.urdf_root: has no effect on cartpole");
  check(R"({"env": {"name": "cartpole"}, "network": {"log_std_init": -1}})", "network.log_std_init: has no effect with discrete");
  check(R"({"env": {"name": "cartpole"}, "network": {"cnn": {"preset": "small"}}})", "network.cnn: has no effect with ground-truth");
  check(R"({"env": {"name": "cartpole"}, "algorithm": "a2c", "a2c": {"optimizer": "adam", "rms_alpha": 0.9}})",
        "a2c.rms_alpha: has no effect with optimizer");
  check(R"({"env": {"name": "cartpole"}, "ppo": {"n_steps": 1, "n_steps": 2}})", "ppo.n_steps: duplicate key");
}

TEST_CASE("the memory a config implies is estimated before anything is allocated", "[train_config][memory]") {
  nlohmann::json j = {{"env", {{"name", "cartpole"}}}, {"network", {{"hidden_sizes", {65536, 65536}}}}};
  const auto big = rdsim::parse_train_config(j, "big.json", "big");
  const rdsim::MemoryEstimate e = rdsim::estimate_training_memory(big, rdsim::config_spec(big));
  CHECK(e.total() > 100e9);  // two 65536 x 65536 layers per network: 4.3e9 weights each
  CHECK_THAT(e.summary(), Contains("network.hidden_sizes"));
  CHECK_THAT(rdsim::test::error_of([&] { rdsim::check_memory(e, rdsim::memory_limit(16.0), "big.json"); }),
             Contains("big.json: this run would need about") && Contains("more than the limit of 16 GB (--max-memory 16)"));
  const auto small = rdsim::read_train_config("configs/cartpole_ppo.json");
  const rdsim::MemoryEstimate s = rdsim::estimate_training_memory(small, rdsim::config_spec(small));
  CHECK(s.total() < 100e6);
  CHECK_NOTHROW(rdsim::check_memory(s, rdsim::memory_limit(std::nullopt), "cartpole_ppo.json"));
  // Pixels scale with the image and the envs: 4096 x 4096 x 64 envs is refused up front.
  j = {{"env", {{"name", "jaka_button"}, {"observation", "raw_pixels"}, {"image_width", 4096}, {"image_height", 4096}}},
       {"num_envs", 64}};
  const auto pixels = rdsim::parse_train_config(j, "pixels.json", "pixels");
  const rdsim::MemoryEstimate p = rdsim::estimate_training_memory(pixels, rdsim::config_spec(pixels));
  CHECK(p.total() > 30e9);
  CHECK_THAT(p.summary(10), Contains("env.image_width x image_height x num_envs"));
  // Every algorithm has its estimate: SAC's replay buffer, CMA-ES's covariance.
  j = {{"env", {{"name", "pendulum"}}}, {"algorithm", "sac"}, {"sac", {{"buffer_size", 100000000}}}};
  const auto sac = rdsim::parse_train_config(j, "sac.json", "sac");
  const rdsim::MemoryEstimate se = rdsim::estimate_training_memory(sac, rdsim::config_spec(sac));
  CHECK(se.total() > 3e9);  // 1e8 transitions of 2 x 3 observation values, 1 action, reward and flag
  CHECK_THAT(se.summary(3), Contains("replay buffer (sac.buffer_size)"));
  j = {{"env", {{"name", "cartpole"}}}, {"algorithm", "cma_es"}, {"network", {{"hidden_sizes", {40}}}}};
  const auto cma = rdsim::parse_train_config(j, "cma.json", "cma");
  CHECK_THAT(rdsim::estimate_training_memory(cma, rdsim::config_spec(cma)).summary(10), Contains("CMA-ES covariance"));
}

TEST_CASE("a run folder is locked by one run at a time, naming the holder", "[run_folder]") {
  rltest::ScratchDir dir("run_folder_lock");
  const std::string run = dir / "run";
  {
    rdsim::RunFolder first(run, rdsim::RunFolder::Mode::New);
    CHECK_THAT(rdsim::test::error_of([&] { rdsim::RunFolder second(run, rdsim::RunFolder::Mode::New); }),
               Contains(run + ": another rdsim run (pid " + std::to_string(::getpid()) + ")"));
  }
  rdsim::RunFolder again(run, rdsim::RunFolder::Mode::New);  // released with the first
  CHECK_THAT(rdsim::test::error_of([&] { rdsim::RunFolder missing(dir / "nope", rdsim::RunFolder::Mode::Resume); }),
             Contains("no such run folder"));
}
