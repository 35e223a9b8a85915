// The robot envs through the real binary: bad assets, the shipped configs, a short learning check.
#include <catch2/catch.hpp>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

// Column `index` (0-based) of a CSV line.
std::string cell(const std::string& line, int index) {
  std::string rest = line;
  for (int k = 0; k < index; ++k) rest = rest.substr(rest.find(',') + 1);
  return rest.substr(0, rest.find(','));
}

// Success rate over the last `n` rows of episodes.csv (column 4 = success).
double last_success_rate(const std::string& episodes_csv, std::size_t n) {
  const auto rows = rltest::lines(rltest::slurp(episodes_csv));
  REQUIRE(rows.size() > n);
  double successes = 0;
  for (std::size_t i = rows.size() - n; i < rows.size(); ++i) successes += std::stod(cell(rows[i], 4));
  return successes / static_cast<double>(n);
}

}  // namespace

TEST_CASE("train: a broken robot URDF exits non-zero with one message naming the file", "[cli][urdf]") {
  ScratchDir dir("cli_bad_urdf");
  // A copy of the asset folder whose Jaka file is malformed XML.
  const std::filesystem::path assets = dir.path / "assets";
  std::filesystem::copy("assets", assets, std::filesystem::copy_options::recursive);
  const std::string urdf = (assets / "jaka" / "jaka_zu7.urdf").string();
  rltest::spit(urdf, "<robot name=\"jaka\"><link name=\"base\">");
  const std::string config = dir / "bad_urdf.json";
  rltest::spit(config, R"({"env": {"name": "jaka_button", "urdf_root": ")" + assets.string() + R"("},
                           "total_timesteps": 1024})");
  const auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "run"), dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
  CHECK_THAT(r.err, StartsWith("rdsim: error: "));
  CHECK_THAT(r.err, Contains(urdf));
  CHECK_FALSE(std::filesystem::exists(dir.path / "run" / "model.bin"));
}

TEST_CASE("the shipped robot configs train, replay, and train again identically", "[cli]") {
  ScratchDir dir("cli_robot_configs");
  for (const char* name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    INFO(name);
    const std::string run = dir / name;
    auto r = run_rdsim(std::string("train --quiet --config configs/") + name + ".json --timesteps 4096 --log-dir " + run,
                       dir);
    REQUIRE(r.exit_code == 0);
    r = run_rdsim("replay " + run + "/model.bin -n 2", dir);
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.out, Contains("over 2 episodes"));
    REQUIRE(rltest::lines(rltest::slurp(run + "/episodes.csv")).size() > 1);  // some episodes finished
    // Same config and seed: the same logs, apart from the steps/s and wall-time columns.
    r = run_rdsim(std::string("train --quiet --config configs/") + name + ".json --timesteps 4096 --log-dir " + run +
                      "_again",
                  dir);
    REQUIRE(r.exit_code == 0);
    CHECK(rltest::drop_columns(rltest::slurp(run + "/progress.csv"), 2) ==
          rltest::drop_columns(rltest::slurp(run + "_again/progress.csv"), 2));
    CHECK(rltest::drop_columns(rltest::slurp(run + "/episodes.csv"), 1) ==
          rltest::drop_columns(rltest::slurp(run + "_again/episodes.csv"), 1));
  }
}

// The full check (configs/jaka_button.json: >= 95% success over the last 100 episodes, about 300k
// steps) is tools/bench/learning.sh; this short one guards against a broken learning path.
TEST_CASE("PPO learns jaka_button with random targets: most of the last 100 episodes succeed within 100k steps",
          "[cli][learning]") {
  ScratchDir dir("cli_jaka_learning");
  const auto r = run_rdsim("train --quiet --config configs/jaka_button.json --timesteps 100000 --log-dir " +
                               (dir / "run"),
                           dir);
  REQUIRE(r.exit_code == 0);
  const double rate = last_success_rate(dir / "run/episodes.csv", 100);
  INFO("success rate of the last 100 episodes after 100k steps: " << rate << " (random play: about 0.1)");
  CHECK(rate > 0.6);
}

TEST_CASE("replay --record writes one PNG per observation, envs that cannot draw say so", "[cli][record]") {
  ScratchDir dir("cli_record");
  const std::string run = dir / "run";
  auto r = run_rdsim("train --quiet --config configs/jaka_button.json --timesteps 1024 --log-dir " + run, dir);
  REQUIRE(r.exit_code == 0);
  r = run_rdsim("replay " + run + "/model.bin -n 1 --record " + (dir / "frames"), dir);
  REQUIRE(r.exit_code == 0);
  // "episode 1: return R, length L, success S": one frame after reset and one per step.
  const std::string out = r.out;
  const auto at = out.find("length ");
  REQUIRE(at != std::string::npos);
  const int length = std::stoi(out.substr(at + 7));
  const std::filesystem::path episode = dir.path / "frames" / "episode_001";
  int frames = 0;
  for (const auto& entry : std::filesystem::directory_iterator(episode)) {
    const std::string png = rltest::slurp(entry.path().string());
    CHECK(png.substr(1, 3) == "PNG");
    ++frames;
  }
  CHECK(frames == length + 1);
  CHECK(std::filesystem::exists(episode / "frame_0000.png"));
  CHECK_THAT(r.out, Contains("wrote " + std::to_string(length + 1) + " frames"));

  r = run_rdsim("train --quiet --config configs/cartpole_ppo.json --timesteps 512 --log-dir " + (dir / "cp"), dir);
  REQUIRE(r.exit_code == 0);
  r = run_rdsim("replay " + (dir / "cp") + "/model.bin -n 1 --record " + (dir / "cp_frames"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("cartpole"));
  CHECK_THAT(r.err, Contains("cannot draw frames"));
}

TEST_CASE("rdsim urdf lists links, joints and limits, the effector candidates, and a reach config that trains "
          "(first contact, item 4)",
          "[cli][urdf]") {
  ScratchDir dir("cli_urdf");
  auto r = run_rdsim("urdf assets/jaka/jaka_zu7_gripper.urdf", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("12 links, 11 joints (8 movable)"));
  CHECK_THAT(r.out, Contains("finger_left_joint            prismatic  gripper_base -> finger_left  [0, 0.0425] m, effort 60"));
  // The arm's tool point first, the fingers after it.
  const std::size_t candidates = r.out.find("effector candidates");
  REQUIRE(candidates != std::string::npos);
  CHECK(r.out.find("gripper_tcp", candidates) < r.out.find("finger_left ", candidates));
  // The skeleton is a config: it draws and trains as it is.
  const nlohmann::json skeleton = nlohmann::json::parse(r.out.substr(r.out.find("\n{") + 1));
  CHECK(skeleton["env"]["effector_link"] == "gripper_tcp");
  CHECK(skeleton["env"]["joints"].size() == 6);
  rltest::spit(dir / "mine.json", skeleton.dump());
  r = run_rdsim("render --config " + (dir / "mine.json") + " --out " + (dir / "mine.png"), dir);
  CHECK(r.exit_code == 0);
  r = run_rdsim("train --quiet --config " + (dir / "mine.json") + " --timesteps 512 --log-dir " + (dir / "run"), dir);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  // A file that is not there: one error naming it.
  r = run_rdsim("urdf " + (dir / "nothing.urdf"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains(dir / "nothing.urdf"));
}

TEST_CASE("rdsim envs --config shows a config's env, every option resolved, and its spaces (first contact, item 4)",
          "[cli][urdf]") {
  ScratchDir dir("cli_envs_config");
  auto r = run_rdsim("envs --config configs/reach_jaka.json", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, StartsWith("configs/reach_jaka.json: env reach\n"));
  CHECK_THAT(r.out, Contains("action: Discrete(6)") || Contains("action: Box(3)"));
  CHECK_THAT(r.out, Contains("observation parts: target_from_effector [0, 3), effector_position [3, 6)\n"));
  // The URDF's path resolved from the config's folder, absolute.
  const nlohmann::json env = nlohmann::json::parse(r.out.substr(r.out.find("\n{") + 1));
  CHECK(env["urdf"] == std::filesystem::absolute("assets/jaka/jaka_zu7.urdf").lexically_normal().string());
  CHECK(env.contains("home_pose"));
  rltest::spit(dir / "bad.json", R"({"env": {"name": "reach", "effector_lnk": "x"}})");
  r = run_rdsim("envs --config " + (dir / "bad.json"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains(dir / "bad.json") && Contains("effector_lnk"));
}

TEST_CASE("configs/reach_panda.json and configs/panda_push.json train pybullet_data's Panda as shipped (first contact, item 4)",
          "[cli][urdf]") {
  // tools/setup.sh links pybullet's robot models at .venv/pybullet_data (never copied into the repository).
  if (!std::filesystem::exists(".venv/pybullet_data/franka_panda/panda.urdf"))
    FAIL(".venv/pybullet_data is missing: run tools/setup.sh (it links pybullet's robot models there)");
  ScratchDir dir("cli_panda_configs");
  for (const auto& [config, steps] : {std::pair{"configs/reach_panda.json", 2048}, std::pair{"configs/panda_push.json", 2400}}) {
    INFO(config);
    const auto r = run_rdsim(std::string("train --quiet --config ") + config + " --timesteps " + std::to_string(steps) +
                                 " --log-dir " + (dir / std::filesystem::path(config).stem().string()),
                             dir);
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.out, Contains(std::to_string(steps) + " timesteps"));
  }
}
