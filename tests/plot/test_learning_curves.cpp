#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "rdsim/core/error.hpp"
#include "rdsim/plot/learning_curves.hpp"
#include "../scratch_dir.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch_dir(const std::string& name) {
  static const rdsim::test::ScratchDir root("plot");  // removed when the test program exits
  const fs::path dir = root.path / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

rdsim::RunCurve curve(const std::string& algorithm, std::vector<double> x, std::vector<double> y) {
  rdsim::RunCurve c;
  c.info.algorithm = algorithm;
  c.x = std::move(x);
  c.y = std::move(y);
  return c;
}

}  // namespace

TEST_CASE("learning curves: mean and standard deviation over seeds on their common range", "[plot]") {
  // Two PPO seeds, y = x and y = x + 2, rows at different x; one A2C run.
  const auto bands = rdsim::mean_over_runs({curve("ppo", {0, 10, 20}, {0, 10, 20}),
                                            curve("ppo", {5, 15, 25}, {7, 17, 27}),
                                            curve("a2c", {0, 100}, {1, 1})},
                                           rdsim::Band::StdDev, 16);
  REQUIRE(bands.size() == 2);
  CHECK(bands[0].algorithm == "a2c");  // sorted by name
  const rdsim::CurveBand& ppo = bands[1];
  CHECK(ppo.runs == 2);
  REQUIRE(ppo.x.size() == 16);
  CHECK(ppo.x.front() == 5);  // both seeds have rows from 5 ...
  CHECK(ppo.x.back() == 20);  // ... to 20
  for (std::size_t i = 0; i < ppo.x.size(); ++i) {
    CHECK(ppo.mean[i] == Approx(ppo.x[i] + 1));
    CHECK(ppo.high[i] - ppo.mean[i] == Approx(std::sqrt(2.0)));  // sample std of {x, x + 2}
    CHECK(ppo.mean[i] - ppo.low[i] == Approx(std::sqrt(2.0)));
  }
  CHECK(bands[0].low == bands[0].mean);  // one run: no band

  const auto range = rdsim::mean_over_runs({curve("ppo", {0, 10}, {0, 0}), curve("ppo", {0, 10}, {1, 4})},
                                           rdsim::Band::MinMax, 3);
  CHECK(range[0].low == std::vector<double>{0, 0, 0});
  CHECK(range[0].high == std::vector<double>{1, 2.5, 4});
}

TEST_CASE("learning curves: --x-max cuts a run at x_max, interpolating its value there", "[plot]") {
  rdsim::RunCurve run = curve("cma_es", {0, 10, 20, 30}, {0, 1, 3, 3});
  run.info.dir = "runs/cma_es/seed1";
  const rdsim::RunCurve cut = rdsim::crop_run_curve(run, 15);
  CHECK(cut.x == std::vector<double>{0, 10, 15});
  CHECK(cut.y == std::vector<double>{0, 1, 2});
  CHECK(cut.info.dir == run.info.dir);
  CHECK(rdsim::crop_run_curve(run, 20).x == std::vector<double>{0, 10, 20});  // a row at x_max: no extra point
  CHECK(rdsim::crop_run_curve(run, 99).x == run.x);                          // shorter than x_max: whole
  CHECK_THROWS_WITH(rdsim::crop_run_curve(curve("ppo", {5, 6}, {0, 0}), 1), Catch::Contains("--x-max"));
  // A long run and a short one share the range up to x_max once cut.
  const auto bands = rdsim::mean_over_runs({rdsim::crop_run_curve(run, 15), curve("ppo", {0, 40}, {0, 0})});
  CHECK(bands[0].x.back() == 15);
}

TEST_CASE("learning curves: runs that share no range or have no values are errors", "[plot]") {
  CHECK_THROWS_WITH(rdsim::mean_over_runs({curve("ppo", {0, 1}, {0, 0}), curve("ppo", {2, 3}, {0, 0})}),
                    Catch::Contains("share no range"));
  CHECK_THROWS_WITH(rdsim::mean_over_runs({curve("ppo", {}, {})}), Catch::Contains("no row"));
}

TEST_CASE("learning curves: a run's curve from progress.csv, skipping empty and malformed rows", "[plot]") {
  const fs::path dir = scratch_dir("curve");
  std::ofstream(dir / "config.json") << R"({"algorithm": "a2c", "env": {"name": "cartpole"}, "seed": 4})";
  std::ofstream(dir / "progress.csv") << "timesteps,success_rate,mean_return\n100,,-5\n200,0.5,-4\nbroken\n300,0.75,-3\n";
  const rdsim::RunCurve c = rdsim::read_run_curve(dir.string(), "timesteps", "success_rate");
  CHECK(c.info.algorithm == "a2c");
  CHECK(c.info.env == "cartpole");
  CHECK(c.x == std::vector<double>{200, 300});
  CHECK(c.y == std::vector<double>{0.5, 0.75});
  CHECK(rdsim::interpolate(c, 250) == Approx(0.625));
  CHECK_THROWS_WITH(rdsim::read_run_curve(dir.string(), "timesteps", "loss"),
                    Catch::Contains("no column \"loss\" (it has: timesteps, success_rate, mean_return)"));
  CHECK_THROWS_AS(rdsim::read_run_curve((dir / "absent").string(), "timesteps", "success_rate"), rdsim::Error);
}

TEST_CASE("learning curves: a progress.csv larger than one piece is read to its end", "[plot]") {
  const fs::path dir = scratch_dir("curve_pieces");
  std::ofstream(dir / "config.json") << R"({"algorithm": "sac", "env": {"name": "stack"}, "seed": 1})";
  {
    std::ofstream out(dir / "progress.csv");
    out << "timesteps,success_rate\n";
    for (int t = 1; t <= 1000; ++t) out << t << "," << t / 1000.0 << "\n";
  }
  const rdsim::RunCurve c = rdsim::read_run_curve(dir.string(), "timesteps", "success_rate", 256);  // ~20 pieces
  REQUIRE(c.x.size() == 1000);
  CHECK(c.x.back() == 1000);
  CHECK(c.y.back() == 1.0);
  CHECK(rdsim::read_run_curve(dir.string(), "timesteps", "success_rate").x == c.x);
}

TEST_CASE("learning curves: another program's run from its episodes.csv, a mean over the last episodes", "[plot]") {
  const fs::path dir = scratch_dir("episodes");
  std::ofstream(dir / "config.json") << R"({"algorithm": "sb3_sac", "env": {"name": "push"}, "seed": 2})";
  {
    std::ofstream out(dir / "episodes.csv");
    out << "episode,timesteps,return,length,success,wall_time\n";
    const int success[] = {0, 1, 1, 0, 1, 1, 1};
    for (int e = 1; e <= 7; ++e) out << e << "," << 50 * e << ",-" << e << ",50," << success[e - 1] << "," << 0.5 * e << "\n";
    out << "8,400,-8,50,,4\n";  // no success value: skipped
  }
  // Window 3: the mean over the episodes so far until there are 3, then over the last 3.
  const rdsim::RunCurve c = rdsim::read_episode_curve(dir.string(), "wall_time", "success", 3);
  CHECK(c.info.algorithm == "sb3_sac");
  CHECK(c.info.env == "push");
  CHECK(c.x == std::vector<double>{0.5, 1, 1.5, 2, 2.5, 3, 3.5});
  const std::vector<double> expected = {0, 0.5, 2 / 3.0, 2 / 3.0, 2 / 3.0, 2 / 3.0, 1};
  REQUIRE(c.y.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) CHECK(c.y[i] == Approx(expected[i]));
  // Read in pieces, with a window longer than the run: the mean of all so far.
  const rdsim::RunCurve all = rdsim::read_episode_curve(dir.string(), "episode", "return", 100, 64);
  CHECK(all.x.size() == 8);
  CHECK(all.y.back() == Approx(-4.5));
  CHECK_THROWS_WITH(rdsim::read_episode_curve(dir.string(), "updates", "success", 3),
                    Catch::Contains("episodes.csv: no column \"updates\" (it has: episode, timesteps, return"));
  // A long run: the running sum is exact after many laps of the window.
  const fs::path long_dir = scratch_dir("episodes_long");
  {
    std::ofstream out(long_dir / "episodes.csv");
    out << "episode,timesteps,return,length,success,wall_time\n";
    for (int e = 1; e <= 10000; ++e) out << e << "," << e << "," << 0.1 * (e % 7) << ",1," << e % 2 << "," << e << "\n";
  }
  const rdsim::RunCurve long_run = rdsim::read_episode_curve(long_dir.string(), "timesteps", "return", 100);
  double last100 = 0;
  for (int e = 9901; e <= 10000; ++e) last100 += 0.1 * (e % 7);
  CHECK(long_run.y.back() == Approx(last100 / 100).epsilon(1e-12));
}

TEST_CASE("learning curves: runs are grouped by env, never averaged across envs", "[plot]") {
  auto on = [](rdsim::RunCurve c, const std::string& env) {
    c.info.env = env;
    c.info.dir = "runs/" + env + "_" + c.info.algorithm;
    return c;
  };
  const std::vector<rdsim::RunCurve> runs = {on(curve("ppo", {0, 10}, {0, 1}), "jaka_button"),
                                             on(curve("ppo", {0, 10}, {400, 500}), "cartpole"),
                                             on(curve("sac", {0, 10}, {0, 1}), "jaka_button")};
  CHECK_THROWS_WITH(rdsim::mean_over_runs(runs),
                    Catch::Contains("runs/cartpole_ppo: its env (cartpole) differs from runs/jaka_button_ppo's (jaka_button)"));
  const auto groups = rdsim::runs_by_env(runs);
  REQUIRE(groups.size() == 2);
  CHECK(groups[0].first == "cartpole");  // envs in name order
  CHECK(groups[0].second.size() == 1);
  CHECK(groups[1].first == "jaka_button");
  REQUIRE(groups[1].second.size() == 2);
  CHECK(rdsim::mean_over_runs(groups[1].second).size() == 2);  // ppo and sac, each its own band
}

TEST_CASE("learning curves: a band of runs of different lengths says it was cut at the shortest", "[plot]") {
  const auto cut = rdsim::mean_over_runs({curve("ppo", {0, 10, 20}, {0, 1, 2}), curve("ppo", {0, 10}, {0, 1})});
  REQUIRE(cut.size() == 1);
  CHECK(cut[0].x.back() == 10);
  CHECK(cut[0].longest_x == 20);
  CHECK(cut[0].cut());
  const auto whole = rdsim::mean_over_runs({curve("ppo", {0, 10}, {0, 1}), curve("ppo", {0, 10}, {2, 3})});
  CHECK_FALSE(whole[0].cut());
}
