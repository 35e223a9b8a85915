#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "rdsim/training/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;

namespace {

rdsim::TrainConfig parse(const std::string& text) {
  return rdsim::parse_train_config(nlohmann::json::parse(text), "cfg.json", "cfg");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const rdsim::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("network.cnn: defaults, custom stacks, round trip through the resolved config", "[train_config][cnn]") {
  const rdsim::TrainConfig plain = parse(R"({"env": {"name": "jaka_button"}})");
  CHECK(plain.algorithm.network.cnn.preset == "auto");
  CHECK(plain.algorithm.network.cnn.channels.empty());
  CHECK(plain.algorithm.network.cnn.fc.empty());

  const rdsim::TrainConfig custom = parse(R"({"env": {"name": "jaka_button", "observation": "raw_pixels"},
      "network": {"cnn": {"preset": "nature", "channels": [8, 16], "kernels": [5, 3], "strides": [2, 1], "fc": [128]}}})");
  CHECK(custom.algorithm.network.cnn.preset == "nature");
  CHECK(custom.algorithm.network.cnn.channels == std::vector<int>{8, 16});
  CHECK(custom.algorithm.network.cnn.kernels == std::vector<int>{5, 3});
  CHECK(custom.algorithm.network.cnn.strides == std::vector<int>{2, 1});
  CHECK(custom.algorithm.network.cnn.fc == std::vector<int>{128});

  const rdsim::TrainConfig again = rdsim::parse_train_config(rdsim::to_json(custom), "resolved.json", "cfg");
  CHECK(again.algorithm.network.cnn.preset == "nature");
  CHECK(again.algorithm.network.cnn.channels == custom.algorithm.network.cnn.channels);
  CHECK(again.algorithm.network.cnn.kernels == custom.algorithm.network.cnn.kernels);
  CHECK(again.algorithm.network.cnn.strides == custom.algorithm.network.cnn.strides);
  CHECK(again.algorithm.network.cnn.fc == custom.algorithm.network.cnn.fc);
}

TEST_CASE("network.cnn: bad values are rejected naming the key", "[train_config][cnn]") {
  auto check = [](const std::string& network, const std::string& key) {
    const std::string msg = error_of(R"({"env": {"name": "jaka_button"}, "network": )" + network + "}");
    INFO(network << " -> " << msg);
    CHECK_THAT(msg, Contains("cfg.json"));
    CHECK_THAT(msg, Contains(key));
  };
  check(R"({"cnn": {"preset": "resnet"}})", "network.cnn.preset");
  check(R"({"cnn": {"channels": [8], "kernels": [3]}})", "network.cnn.strides");
  check(R"({"cnn": {"channels": [8], "kernels": [3, 3], "strides": [1]}})", "network.cnn.kernels");
  check(R"({"cnn": {"channels": [0], "kernels": [3], "strides": [1]}})", "network.cnn.channels");
  check(R"({"cnn": {"fc": [-4]}})", "network.cnn.fc");
  check(R"({"cnn": {"dropout": 0.5}})", "network.cnn.dropout");
  check(R"({"cnn": "small"})", "network.cnn");
}

TEST_CASE("train -> replay with a CNN policy on jaka_button raw pixels", "[cli][cnn]") {
  rltest::ScratchDir dir("cli_cnn");
  const std::string config = dir / "pixels.json";
  rltest::spit(config, R"({
    "algorithm": "ppo", "env": {"name": "jaka_button", "observation": "raw_pixels", "max_steps": 20,
                                "image_width": 32, "image_height": 32},
    "seed": 2, "total_timesteps": 128, "num_envs": 2,
    "network": {"cnn": {"channels": [8], "kernels": [4], "strides": [4], "fc": [16]}},
    "ppo": {"n_steps": 32, "batch_size": 32, "n_epochs": 1}
  })");
  auto r = rltest::run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "run"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // Replay rebuilds the pixel env and the CNN from model.bin alone; same seed => same episodes.
  const auto a = rltest::run_rdsim("replay " + (dir / "run/model.bin") + " -n 2 --seed 5", dir);
  const auto b = rltest::run_rdsim("replay " + (dir / "run/model.bin") + " -n 2 --seed 5", dir);
  INFO(a.err);
  REQUIRE(a.exit_code == 0);
  CHECK_THAT(a.out, Contains("episode 2"));
  CHECK(a.out == b.out);
}

TEST_CASE("train -> replay -> export with CNN policies on Float32 colour, depth and segmentation", "[cli][cnn]") {
  // image_channels: the CNN reads the stacked Float32 channels as they are (PPO, and DQN, whose
  // replay buffer keeps them as floats); replay rebuilds the env; the ONNX export matches rdsim.
  rltest::ScratchDir dir("cli_cnn_channels");
  for (const std::string algorithm : {"ppo", "dqn"}) {
    INFO(algorithm);
    const std::string config = dir / (algorithm + ".json");
    rltest::spit(config, R"({
      "algorithm": ")" + algorithm + R"(", "env": {"name": "jaka_button", "observation": "raw_pixels", "max_steps": 20,
                                  "image_width": 32, "image_height": 32, "image_channels": "rgb_depth_segmentation"},
      "seed": 2, "total_timesteps": 128, "num_envs": 2,
      "network": {"cnn": {"channels": [8], "kernels": [4], "strides": [4], "fc": [16]}},
      )" + (algorithm == "ppo" ? R"("ppo": {"n_steps": 32, "batch_size": 32, "n_epochs": 1})"
                               : R"("dqn": {"learning_starts": 64, "batch_size": 16, "buffer_size": 256})") + R"(
    })");
    const std::string run = dir / ("run_" + algorithm);
    auto r = rltest::run_rdsim("train --quiet --config " + config + " --log-dir " + run, dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto a = rltest::run_rdsim("replay " + run + "/model.bin -n 2 --seed 5", dir);
    INFO(a.err);
    REQUIRE(a.exit_code == 0);
    CHECK_THAT(a.out, Contains("episode 2"));
    const auto e = rltest::run_rdsim("export " + run + "/model.bin --onnx " + run + "/policy.onnx", dir);
    INFO(e.err);
    CHECK(e.exit_code == 0);
    CHECK(std::filesystem::exists(run + "/policy.onnx"));
  }
}
