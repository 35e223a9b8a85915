// `rdsim bench-fps`: env steps per second in the shape of the paper's Table 3.
#include "rdsim/app/bench_fps.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/registry.hpp"
#include "bench_util.hpp"

namespace rdsim {
namespace {

using Clock = std::chrono::steady_clock;

struct BenchRow {
  std::string env;
  std::string mode;
  int image_size = 0;                      // raw_pixels: square image side; 0 for ground truth
  double steps_per_s = 0;                  // median over runs
  std::vector<double> runs;                // every run, for the JSON
  std::optional<double> physics_per_s;     // bare physics steps/s of the same world
  std::optional<double> paper_steps_per_s; // RobotDrlSim Table 3, where the paper has the row
  long long episodes = 0;
};

// RobotDrlSim (MSOTA 2020) Table 3, measured on the authors' machine with PyBullet; its pixel
// rows are 224x224 images, so other sizes have no paper figure to compare with.
constexpr int kPaperImageSize = 224;

std::optional<double> paper_rate(const std::string& env, const std::string& mode, int image_size) {
  const bool pixels = mode == "raw_pixels";
  if (pixels && image_size != kPaperImageSize) return std::nullopt;
  if (env.rfind("jaka", 0) == 0) return pixels ? 22.0 : 506.0;
  if (env.rfind("inmoov", 0) == 0) return pixels ? 8.0 : 76.0;
  return std::nullopt;
}

using bench::Clock;
using bench::median;
using bench::seconds_since;

// One timed run: random actions, resets included (as an agent would see it).
double env_run(Env& env, long long steps, std::uint64_t seed, long long& episodes) {
  const std::vector<Action> actions =
      bench::random_actions(env.spec().action, static_cast<size_t>(std::min<long long>(steps, 4096)), seed);
  env.reset(seed);
  const auto t0 = Clock::now();
  for (long long i = 0; i < steps; ++i) {
    StepResult r = env.step(actions[static_cast<size_t>(i) % actions.size()]);
    if (r.terminated || r.truncated) {
      env.reset();
      ++episodes;
    }
  }
  return static_cast<double>(steps) / seconds_since(t0);
}

std::optional<double> physics_run(Env& env, long long steps, std::uint64_t seed) {
  env.reset(seed);
  if (!env.step_physics_only()) return std::nullopt;
  const auto t0 = Clock::now();
  for (long long i = 0; i < steps; ++i) env.step_physics_only();
  return static_cast<double>(steps) / seconds_since(t0);
}

std::optional<BenchRow> bench_row(const EnvEntry& entry, const std::string& mode, int image_size,
                                  const BenchFpsOptions& o) {
  std::unique_ptr<Env> env;
  try {
    env = entry.make(bench::row_config(entry.name, mode, image_size));
  } catch (const Error& e) {
    std::fprintf(stderr, "bench-fps: skipping %s / %s: %s\n", entry.name.c_str(), mode.c_str(), e.what());
    return std::nullopt;
  }
  BenchRow row{entry.name, mode, image_size, 0, {}, std::nullopt, paper_rate(entry.name, mode, image_size), 0};
  long long warmup_episodes = 0;
  env_run(*env, std::max<long long>(o.steps / 10, 100), 12345, warmup_episodes);
  std::vector<double> physics;
  for (int r = 0; r < o.runs; ++r) {
    row.runs.push_back(env_run(*env, o.steps, static_cast<std::uint64_t>(r), row.episodes));
    if (auto p = physics_run(*env, o.steps, static_cast<std::uint64_t>(r))) physics.push_back(*p);
  }
  row.steps_per_s = median(row.runs);
  if (!physics.empty()) row.physics_per_s = median(physics);
  return row;
}

std::string fmt(double v, const char* spec = "%.0f") {
  char buf[64];
  std::snprintf(buf, sizeof buf, spec, v);
  return buf;
}

void print_table(std::FILE* out, const std::vector<BenchRow>& rows, const BenchFpsOptions& o) {
  std::fprintf(out, "\nrdsim bench-fps: env steps/s on one thread, random actions, resets included\n");
  std::fprintf(out, "median of %d runs x %lld steps; physics = the same world stepped with no env work\n\n",
              o.runs, o.steps);
  std::fprintf(out, "%-16s %-13s %9s %12s %14s %12s %11s %12s\n", "env", "observation", "image",
              "steps/s", "physics st/s", "env/physics", "paper st/s", "vs paper");
  for (const auto& r : rows) {
    std::string phys = r.physics_per_s ? fmt(*r.physics_per_s) : "-";
    std::string ratio = r.physics_per_s ? fmt(*r.physics_per_s / r.steps_per_s, "%.2fx") : "-";
    std::string paper = r.paper_steps_per_s ? fmt(*r.paper_steps_per_s) : "-";
    std::string gain = r.paper_steps_per_s ? fmt(r.steps_per_s / *r.paper_steps_per_s, "%.0fx") : "-";
    const std::string image = bench::image_label(r.image_size);
    std::fprintf(out, "%-16s %-13s %9s %12.0f %14s %12s %11s %12s\n", r.env.c_str(), r.mode.c_str(),
                image.c_str(), r.steps_per_s, phys.c_str(), ratio.c_str(), paper.c_str(), gain.c_str());
  }
  std::fprintf(out, "\nenv/physics: cost of one env step over the bare physics step(s) it contains.\n");
  std::fprintf(out, "paper: RobotDrlSim Table 3 (PyBullet); its raw-pixel rows are %dx%d images.\n",
              kPaperImageSize, kPaperImageSize);
}

nlohmann::json to_json(const std::vector<BenchRow>& rows, const BenchFpsOptions& o) {
  nlohmann::json j = {{"runs", o.runs}, {"steps_per_run", o.steps}, {"threads", 1}, {"rows", nlohmann::json::array()}};
  for (const auto& r : rows) {
    nlohmann::json row = {{"env", r.env}, {"observation", r.mode},
                          {"image_size", r.image_size > 0 ? nlohmann::json(r.image_size) : nlohmann::json(nullptr)},
                          {"steps_per_s", r.steps_per_s},
                          {"runs_steps_per_s", r.runs}, {"episodes", r.episodes}};
    row["physics_steps_per_s"] = r.physics_per_s ? nlohmann::json(*r.physics_per_s) : nlohmann::json(nullptr);
    row["paper_steps_per_s"] = r.paper_steps_per_s ? nlohmann::json(*r.paper_steps_per_s) : nlohmann::json(nullptr);
    j["rows"].push_back(row);
  }
  return j;
}

std::vector<int> pixel_sizes(const BenchFpsOptions& o) {
  if (o.image_sizes.empty()) return {64, kPaperImageSize};
  for (int size : o.image_sizes)
    if (size < 1 || size > 4096)
      throw Error("bench-fps: --image-size: expected 1..4096 pixels, got " + std::to_string(size));
  return o.image_sizes;
}

bool wanted(const std::vector<std::string>& filter, const std::string& value) {
  return filter.empty() || std::find(filter.begin(), filter.end(), value) != filter.end();
}

}  // namespace

namespace bench {

EnvConfig row_config(const std::string& env, const std::string& mode, int image_size) {
  EnvConfig config = default_env_config(env);
  config.observation = mode == "raw_pixels" ? ObservationMode::RawPixels : ObservationMode::GroundTruth;
  if (image_size > 0) config.image_width = config.image_height = image_size;
  return config;
}

std::FILE* table_stream(const BenchFpsOptions& o) { return o.json_path == "-" ? stderr : stdout; }

void emit_json(const nlohmann::json& j, const BenchFpsOptions& o) {
  if (o.json_path == "-") {
    std::cout << j.dump(2) << "\n";
  } else if (!o.json_path.empty()) {
    write_file_atomic(o.json_path, j.dump(2) + "\n");
    std::printf("wrote %s\n", o.json_path.c_str());
  }
}

void announce(const Case& c) {
  std::fprintf(stderr, "bench-fps: %s / %s", c.entry->name.c_str(), c.mode.c_str());
  if (c.image_size > 0) std::fprintf(stderr, " %dx%d", c.image_size, c.image_size);
  std::fprintf(stderr, " ...\n");
}

}  // namespace bench

int bench_fps_command(const BenchFpsOptions& o) {
  for (const auto& name : o.envs) (void)env_entry(name);  // the "unknown environment" error with the known names
  std::vector<bench::Case> cases;
  for (const auto& entry : env_registry()) {
    if (!wanted(o.envs, entry.name)) continue;
    for (std::string mode : {"ground_truth", "raw_pixels"}) {
      if (!wanted(o.modes, mode) || (mode == "raw_pixels" && !entry.supports_pixels)) continue;
      // Ground truth has no image: one row with size 0.
      const std::vector<int> sizes = mode == "raw_pixels" ? pixel_sizes(o) : std::vector<int>{0};
      for (int size : sizes) cases.push_back({&entry, mode, size});
    }
  }
  if (cases.empty()) throw Error("bench-fps: nothing to measure for the given --env/--mode");
  if (o.threads > 0 || o.scaling) return bench::threads_command(cases, o);

  std::vector<BenchRow> rows;
  for (const bench::Case& c : cases) {
    bench::announce(c);
    if (auto row = bench_row(*c.entry, c.mode, c.image_size, o)) rows.push_back(std::move(*row));
  }
  if (rows.empty()) throw Error("bench-fps: nothing to measure for the given --env/--mode");
  // With JSON on stdout the human table goes to stderr, so the JSON stays machine-readable.
  print_table(bench::table_stream(o), rows, o);
  bench::emit_json(to_json(rows, o), o);
  return 0;
}

}  // namespace rdsim
