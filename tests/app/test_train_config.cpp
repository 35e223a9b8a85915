#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "rdsim/app/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rl_test_util.hpp"

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
