#include <catch2/catch.hpp>
#include <filesystem>

#include "rl_test_util.hpp"

namespace fs = std::filesystem;

namespace {

void fake_run(const fs::path& dir, const std::string& algorithm, int seed, double speed,
              const std::string& env = "jaka_button", int updates = 50) {
  fs::create_directories(dir);
  rltest::spit((dir / "config.json").string(), "{\"algorithm\": \"" + algorithm +
                                                   "\", \"env\": {\"name\": \"" + env + "\"}, \"seed\": " +
                                                   std::to_string(seed) + "}");
  std::string csv = "timesteps,updates,mean_return,success_rate,wall_time\n";
  for (int i = 1; i <= updates; ++i) {
    csv += std::to_string(i * 2048) + "," + std::to_string(i) + "," + std::to_string(-50 + i * speed) + "," +
           std::to_string(std::min(1.0, i * speed / 50)) + "," + std::to_string(0.0125 * i) + "\n";
  }
  rltest::spit((dir / "progress.csv").string(), csv);
}

}  // namespace

TEST_CASE("plot: a learning-curve figure from run folders, one band per algorithm", "[cli][plot]") {
  rltest::ScratchDir dir("plot_cli");
  fake_run(dir.path / "runs" / "ppo_1", "ppo", 1, 1.0);
  fake_run(dir.path / "runs" / "ppo_2", "ppo", 2, 1.2);
  fake_run(dir.path / "runs" / "a2c_1", "a2c", 1, 0.5);
  const auto r = rltest::run_rdsim("plot " + dir / "runs" + " --out " + dir / "success.png", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(rltest::slurp(dir / "success.png").substr(0, 8) == "\x89PNG\r\n\x1a\n");
  CHECK(r.out.find("ppo (2 runs): success rate at timesteps 102400: 1.000") != std::string::npos);
  CHECK(r.out.find("a2c (1 run)") != std::string::npos);

  const auto svg = rltest::run_rdsim("plot " + dir / "runs/ppo_1" + " " + dir / "runs/ppo_2" + " --out " + dir / "r.svg" +
                                         " --metric return --x updates --band minmax",
                                     dir);
  REQUIRE(svg.exit_code == 0);
  CHECK(rltest::slurp(dir / "r.svg").find("<svg") != std::string::npos);
  CHECK(svg.out.find("mean return at updates 50: 5.000 (band 0.000 to 10.000)") != std::string::npos);
}

TEST_CASE("plot: another program's runs (config.json and episodes.csv) beside rdsim's, against wall-clock", "[cli][plot]") {
  rltest::ScratchDir dir("plot_cli_episodes");
  fake_run(dir.path / "runs" / "sac_1", "sac", 1, 1.0);
  // As examples/sb3_her.py --log-dir writes them: ten episodes a second, every other one a success.
  const fs::path other = dir.path / "runs" / "sb3_1";
  fs::create_directories(other);
  rltest::spit((other / "config.json").string(), R"({"algorithm": "sb3_sac", "env": {"name": "jaka_button"}, "seed": 1})");
  std::string csv = "episode,timesteps,return,length,success,wall_time\n";
  for (int e = 1; e <= 300; ++e) csv += std::to_string(e) + "," + std::to_string(50 * e) + ",-10,50," + std::to_string(e % 2) + "," + std::to_string(0.1 * e) + "\n";
  rltest::spit((other / "episodes.csv").string(), csv);
  auto r = rltest::run_rdsim("plot " + dir / "runs" + " --out " + dir / "wall.png --x wall_time --window 50", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("sac (1 run): success rate at wall_time 0.625") != std::string::npos);
  CHECK(r.out.find("sb3_sac (1 run): success rate at wall_time 30: 0.500") != std::string::npos);
  // What episodes.csv cannot give is one message naming the run.
  r = rltest::run_rdsim("plot " + other.string() + " --out " + dir / "x.png --metric kl", dir);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("sb3_1: no progress.csv, and its episodes.csv gives --metric success, return or length only, not \"kl\"") !=
        std::string::npos);
  r = rltest::run_rdsim("plot " + other.string() + " --out " + dir / "x.png --x updates", dir);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("has no --x updates") != std::string::npos);
}

TEST_CASE("plot: missing runs, columns and bad file names fail with one message", "[cli][plot]") {
  rltest::ScratchDir dir("plot_cli_errors");
  fake_run(dir.path / "run", "ppo", 1, 1.0);
  auto r = rltest::run_rdsim("plot " + dir / "run" + " --out " + dir / "x.png --metric entropy", dir);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("no column \"entropy\"") != std::string::npos);
  r = rltest::run_rdsim("plot " + dir / "nothing" + " --out " + dir / "x.png", dir);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("not a folder") != std::string::npos);
  r = rltest::run_rdsim("plot " + dir / "run" + " --out " + dir / "x.gif", dir);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find(".png or .svg") != std::string::npos);
}

TEST_CASE("plot: runs of different envs get a panel each, never one pooled curve", "[cli][plot]") {
  rltest::ScratchDir dir("plot_cli_envs");
  fake_run(dir.path / "runs" / "ppo_button", "ppo", 1, 1.0, "jaka_button");
  fake_run(dir.path / "runs" / "ppo_cartpole", "ppo", 1, 2.0, "cartpole");
  fake_run(dir.path / "runs" / "ppo_cartpole_2", "ppo", 2, 2.0, "cartpole");
  const auto r = rltest::run_rdsim("plot " + dir / "runs" + " --out " + dir / "figures/success.png", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);  // the figure's folder is made
  CHECK_THAT(r.out, Catch::Contains("from 3 runs, 2 envs (one panel each)"));
  CHECK_THAT(r.out, Catch::Contains("  cartpole, ppo (2 runs): success rate at timesteps 102400"));
  CHECK_THAT(r.out, Catch::Contains("  jaka_button, ppo (1 run): success rate at timesteps 102400"));
  // Two panels of the default 480 pixels, one below the other: the PNG's height (IHDR, bytes 20..23).
  const std::string png = rltest::slurp(dir / "figures/success.png");
  REQUIRE(png.size() > 24);
  CHECK((static_cast<unsigned char>(png[22]) << 8 | static_cast<unsigned char>(png[23])) == 960);
}

TEST_CASE("plot: runs of different lengths: the cut at the shortest is said, x values are not rounded to 0", "[cli][plot]") {
  rltest::ScratchDir dir("plot_cli_lengths");
  fake_run(dir.path / "runs" / "long", "ppo", 1, 1.0, "jaka_button", 50);
  fake_run(dir.path / "runs" / "short", "ppo", 2, 1.0, "jaka_button", 20);
  auto r = rltest::run_rdsim("plot " + dir / "runs" + " --out " + dir / "s.png", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Catch::Contains("ppo (2 runs): success rate at timesteps 40960: 0.400 (band 0.400 to 0.400); cut at "
                                    "the shortest run (the longest reached timesteps 102400)"));
  r = rltest::run_rdsim("plot " + dir / "runs" + " --out " + dir / "w.png --x wall_time", dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Catch::Contains("success rate at wall_time 0.25: ") &&
                        Catch::Contains("(the longest reached wall_time 0.625)"));
}
