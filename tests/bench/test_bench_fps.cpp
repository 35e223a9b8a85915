// `rdsim bench-fps`: raw-pixel rows per image size, in the table and the JSON.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "bench_json.hpp"
#include "rdsim/bench/bench_fps.hpp"
#include "rdsim/core/error.hpp"

using namespace rdsim;

namespace {

nlohmann::json run_bench(BenchFpsOptions o) {
  o.runs = 1;
  o.steps = 20;
  return test::bench_json(o, bench_fps_command, "bench_fps");
}

}  // namespace

TEST_CASE("bench-fps: one raw-pixel row per --image-size, the paper figure only at 224", "[bench]") {
  BenchFpsOptions o;
  o.envs = {"jaka_button"};
  o.image_sizes = {16, 224};
  const nlohmann::json j = run_bench(o);
  const nlohmann::json& rows = j.at("rows");
  REQUIRE(rows.size() == 3);  // ground truth, pixels 16x16, pixels 224x224
  CHECK(rows[0].at("observation") == "ground_truth");
  CHECK(rows[0].at("image_size").is_null());
  CHECK(rows[0].at("paper_steps_per_s") == 506.0);
  CHECK(rows[1].at("observation") == "raw_pixels");
  CHECK(rows[1].at("image_size") == 16);
  CHECK(rows[1].at("paper_steps_per_s").is_null());
  CHECK(rows[2].at("image_size") == 224);
  CHECK(rows[2].at("paper_steps_per_s") == 22.0);
  for (const auto& row : rows) CHECK(row.at("steps_per_s").get<double>() > 0.0);
}

TEST_CASE("bench-fps: pixel rows default to 64 and 224, bad sizes are refused", "[bench]") {
  BenchFpsOptions o;
  o.envs = {"jaka_button"};
  o.modes = {"raw_pixels"};
  const nlohmann::json rows = run_bench(o).at("rows");
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].at("image_size") == 64);
  CHECK(rows[1].at("image_size") == 224);

  o.image_sizes = {0};
  CHECK_THROWS_WITH(bench_fps_command(o), Catch::Contains("--image-size") && Catch::Contains("0"));
}

TEST_CASE("bench-fps: one raw-pixel row per --image-channels, named in the JSON", "[bench]") {
  BenchFpsOptions o;
  o.envs = {"jaka_button"};
  o.modes = {"raw_pixels"};
  o.image_sizes = {16};
  o.image_channels = {"rgb", "rgb_depth_segmentation"};
  const nlohmann::json rows = run_bench(o).at("rows");
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].at("image_channels") == "rgb");
  CHECK(rows[1].at("image_channels") == "rgb_depth_segmentation");
  for (const auto& row : rows) CHECK(row.at("steps_per_s").get<double>() > 0.0);
}

TEST_CASE("bench-fps --paper: each mode's paper preset next to the defaults, with the work per step", "[bench]") {
  BenchFpsOptions o;
  o.envs = {"jaka_button"};
  o.paper = true;
  const nlohmann::json rows = run_bench(o).at("rows");
  REQUIRE(rows.size() == 4);  // ground truth: paper, default; 224x224 pixels: paper, default
  for (size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json& row = rows[i];
    const bool paper = i % 2 == 0;
    INFO(row.dump());
    CHECK(row.at("preset") == (paper ? "paper" : "default"));
    CHECK(row.at("observation") == (i < 2 ? "ground_truth" : "raw_pixels"));
    if (i >= 2) CHECK(row.at("image_size") == 224);
    CHECK(row.at("paper_steps_per_s") == (i < 2 ? 506.0 : 22.0));
    CHECK(row.at("action_repeat") == (paper ? 2 : 1));
    CHECK(row.at("solver_iterations") == (paper ? 150 : 10));
    CHECK(row.at("ik_iterations") == (paper ? 20 : 1));
    CHECK(row.at("steps_per_s").get<double>() > 0.0);
  }
}

TEST_CASE("bench-fps --threads: pixel envs on threads and on worker processes with speed-ups over one worker", "[bench]") {
  BenchFpsOptions o;
  o.envs = {"jaka_button"};
  o.image_sizes = {16};
  o.threads = 2;
  o.num_envs = 4;
  const nlohmann::json rows = run_bench(o).at("rows");
  REQUIRE(rows.size() == 2);  // ground truth, pixels 16x16
  auto kinds = [](const nlohmann::json& row) {
    std::vector<std::pair<int, std::string>> out;
    for (const auto& t : row.at("threads")) {
      const int groups = t.at("env_groups").get<int>();
      out.emplace_back(t.at("threads").get<int>(), t.at("env_workers").get<std::string>() + (groups > 1 ? ", 2 groups" : ""));
      CHECK(t.at("steps_per_s").get<double>() > 0.0);
    }
    return out;
  };
  using Kinds = std::vector<std::pair<int, std::string>>;
  // Groups in turn only where they overlap: envs any worker may step (not pixel envs).
  CHECK(kinds(rows[0]) == Kinds{{1, "threads"}, {2, "threads"}, {2, "threads, 2 groups"}});
  CHECK(kinds(rows[1]) == Kinds{{1, "threads"}, {2, "threads"}, {2, "processes"}});
  CHECK(rows[0].at("cache_line_round_trip_ns_runs").size() == 1);
  CHECK(rows[1].at("threads")[0].at("speedup") == 1.0);
  CHECK(rows[1].at("envs") == 4);
}

TEST_CASE("bench-fps --set: env keys on every row, in its env_config, and a bad one is one error", "[bench]") {
  BenchFpsOptions o;
  o.envs = {"push"};
  o.modes = {"ground_truth"};
  o.settings = {"substeps=5", "physics_step=0.008", "randomize={\"action_latency\": 1}"};
  const nlohmann::json j = run_bench(o);
  CHECK(j.at("settings").size() == 3);
  const nlohmann::json& rows = j.at("rows");
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].at("env_config").at("substeps") == 5);
  CHECK(rows[0].at("env_config").at("physics_step") == 0.008);
  CHECK(rows[0].at("env_config").at("randomize").at("action_latency") == 1);
  CHECK(rows[0].at("steps_per_s").get<double>() > 0.0);
  o.settings = {"substeps"};
  CHECK_THROWS_WITH(bench_fps_command(o), Catch::Contains("bench-fps: --set: expected KEY=VALUE"));
  o.settings = {"substeps=0"};
  CHECK_THROWS_WITH(bench_fps_command(o), Catch::Contains("bench-fps --set: env.substeps: expected an integer"));
  o.settings = {"substepz=5"};
  CHECK_THROWS_WITH(bench_fps_command(o), Catch::Contains("env.substepz") && Catch::Contains("did you mean"));
  o.envs = {"jaka_button"};
  o.settings = {"substeps=5"};
  CHECK_THROWS_WITH(bench_fps_command(o), Catch::Contains("env.substeps: has no effect on jaka_button"));
}
