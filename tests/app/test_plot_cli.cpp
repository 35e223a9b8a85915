#include <catch2/catch.hpp>
#include <filesystem>

#include "rl_test_util.hpp"

namespace fs = std::filesystem;

namespace {

void fake_run(const fs::path& dir, const std::string& algorithm, int seed, double speed) {
  fs::create_directories(dir);
  rltest::spit((dir / "config.json").string(), "{\"algorithm\": \"" + algorithm +
                                                   "\", \"env\": {\"name\": \"jaka_button\"}, \"seed\": " +
                                                   std::to_string(seed) + "}");
  std::string csv = "timesteps,updates,mean_return,success_rate\n";
  for (int i = 1; i <= 50; ++i) {
    csv += std::to_string(i * 2048) + "," + std::to_string(i) + "," + std::to_string(-50 + i * speed) + "," +
           std::to_string(std::min(1.0, i * speed / 50)) + "\n";
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
