// `rdsim bench-fps`: env steps per second in the shape of the paper's Table 3.
#include "rdsim/bench/bench_fps.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "rdsim/bench/bench_run.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "bench_util.hpp"

namespace rdsim {
namespace {

using bench::Clock;
using bench::seconds_since;

struct BenchRow {
  std::string env;
  std::string mode;
  std::string preset;                      // "default" or "paper" (configs/paper/)
  int image_size = 0;                      // raw_pixels: square image side; 0 for ground truth
  std::string image_channels = "rgb";      // raw_pixels: EnvConfig::image_channels
  int action_repeat = 0, solver_iterations = 0, ik_iterations = 0;  // the per-step work (robot envs)
  double steps_per_s = 0;                  // median over runs
  std::vector<double> runs;                // every run, for the JSON
  std::optional<double> physics_per_s;     // bare physics steps/s of the same world
  std::optional<double> paper_steps_per_s; // RobotDrlSim Table 3, where the paper has the row
  long long episodes = 0;
  nlohmann::json env_config;               // every env key with the value measured
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

std::optional<double> physics_run(Env& env, long long steps, std::uint64_t seed) {
  env.reset(seed);
  if (!env.step_physics_only()) return std::nullopt;
  const auto t0 = Clock::now();
  for (long long i = 0; i < steps; ++i) env.step_physics_only();
  return static_cast<double>(steps) / seconds_since(t0);
}

// One measured row: `config`'s env, warmed up, then o.runs timed runs (and bare physics runs).
std::optional<BenchRow> bench_row(const EnvConfig& config, const std::string& preset, const BenchFpsOptions& o) {
  const EnvEntry& entry = env_entry(config.name);
  const std::string mode = to_string(config.observation);
  const bool pixels = config.observation == ObservationMode::RawPixels;
  const int image_size = pixels ? config.image_width : 0;
  std::fprintf(stderr, "bench-fps: %s / %s", entry.name.c_str(), mode.c_str());
  if (pixels) std::fprintf(stderr, " %dx%d", config.image_width, config.image_height);
  if (pixels && config.image_channels != "rgb") std::fprintf(stderr, " %s", config.image_channels.c_str());
  std::fprintf(stderr, "%s ...\n", preset == "default" ? "" : (" / " + preset + " preset").c_str());
  std::unique_ptr<Env> env;
  try {
    env = make_env(config);
  } catch (const Error& e) {
    std::fprintf(stderr, "bench-fps: skipping %s / %s: %s\n", entry.name.c_str(), mode.c_str(), e.what());
    return std::nullopt;
  }
  BenchRow row;
  row.env = entry.name;
  row.mode = mode;
  row.preset = preset;
  row.image_size = image_size;
  row.image_channels = config.image_channels;
  row.paper_steps_per_s = paper_rate(entry.name, mode, image_size);
  row.env_config = to_json(config);
  if (const auto* reach = config.find<ReachOptions>()) {  // the reaching envs: what one env step simulates
    row.action_repeat = reach->action_repeat;
    row.solver_iterations = reach->solver_iterations;
    row.ik_iterations = reach->ik_iterations;
  }
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

std::string paper_preset_path(const std::string& env, const std::string& mode) {
  return repo_root() + "/configs/paper/" + env + (mode == "raw_pixels" ? "_pixels" : "") + ".json";
}

// The "env" object of configs/paper/<env>[_pixels].json, read by the rules of a training config.
EnvConfig paper_preset(const std::string& env, const std::string& mode) {
  return read_train_config(paper_preset_path(env, mode)).env;
}

std::string fmt(double v, const char* spec = "%.0f") {
  char buf[64];
  std::snprintf(buf, sizeof buf, spec, v);
  return buf;
}

void print_table(std::FILE* out, const std::vector<BenchRow>& rows, const BenchFpsOptions& o) {
  std::fprintf(out, "\nrdsim bench-fps: env steps/s on one thread, random actions, resets included\n");
  std::fprintf(out, "median of %d runs x %lld steps; physics = the same world stepped with no env work\n",
              o.runs, o.steps);
  if (!o.settings.empty()) {
    std::string set;
    for (const std::string& s : o.settings) set += " " + s;
    std::fprintf(out, "env keys set on every row:%s\n", set.c_str());
  }
  std::fprintf(out, "\n");
  int image_width = 9;  // the image column: "224x224", or wider with named channels
  for (const auto& r : rows)
    image_width = std::max(image_width, static_cast<int>(bench::image_label(r.image_size, r.image_channels).size()));
  std::fprintf(out, "%-16s %-13s %*s ", "env", "observation", image_width, "image");
  if (o.paper) std::fprintf(out, "%-8s %13s ", "preset", "work/step");
  std::fprintf(out, "%12s %14s %12s %11s %12s\n", "steps/s", "physics st/s", "env/physics", "paper st/s", "vs paper");
  for (const auto& r : rows) {
    std::string phys = r.physics_per_s ? fmt(*r.physics_per_s) : "-";
    std::string ratio = r.physics_per_s ? fmt(*r.physics_per_s / r.steps_per_s, "%.2fx") : "-";
    std::string paper = r.paper_steps_per_s ? fmt(*r.paper_steps_per_s) : "-";
    std::string gain = "-";
    if (r.paper_steps_per_s) {  // two decimals below 10x, so that a slower row does not read "0x"
      const double g = r.steps_per_s / *r.paper_steps_per_s;
      gain = fmt(g, g < 10.0 ? "%.2fx" : "%.0fx");
    }
    const std::string image = bench::image_label(r.image_size, r.image_channels);
    std::fprintf(out, "%-16s %-13s %*s ", r.env.c_str(), r.mode.c_str(), image_width, image.c_str());
    if (o.paper) {
      const std::string work = std::to_string(r.action_repeat) + "/" + std::to_string(r.solver_iterations) + "/" +
                               std::to_string(r.ik_iterations);
      std::fprintf(out, "%-8s %13s ", r.preset.c_str(), work.c_str());
    }
    std::fprintf(out, "%12.0f %14s %12s %11s %12s\n", r.steps_per_s, phys.c_str(), ratio.c_str(), paper.c_str(),
                gain.c_str());
  }
  std::fprintf(out, "\nenv/physics: cost of one env step over the bare physics step(s) it contains.\n");
  if (o.paper) {
    std::fprintf(out, "work/step: physics steps / solver iterations / IK iterations per env step.\n");
    std::fprintf(out, "paper preset: configs/paper/ (the original's per-step work); default: the env's defaults.\n");
  }
  std::fprintf(out, "paper: RobotDrlSim Table 3 (PyBullet, the authors' machine: a ratio to it is across\n"
                    "machines); its raw-pixel rows are %dx%d images.\n", kPaperImageSize, kPaperImageSize);
}

nlohmann::json to_json(const std::vector<BenchRow>& rows, const BenchFpsOptions& o) {
  nlohmann::json j = {{"runs", o.runs}, {"steps_per_run", o.steps}, {"threads", 1}, {"settings", o.settings},
                      {"rows", nlohmann::json::array()}};
  for (const auto& r : rows) {
    nlohmann::json row = {{"env", r.env}, {"observation", r.mode}, {"preset", r.preset},
                          {"image_size", r.image_size > 0 ? nlohmann::json(r.image_size) : nlohmann::json(nullptr)},
                          {"image_channels", r.image_size > 0 ? nlohmann::json(r.image_channels) : nlohmann::json(nullptr)},
                          {"steps_per_s", r.steps_per_s},
                          {"runs_steps_per_s", r.runs}, {"episodes", r.episodes}, {"env_config", r.env_config}};
    row["physics_steps_per_s"] = r.physics_per_s ? nlohmann::json(*r.physics_per_s) : nlohmann::json(nullptr);
    row["paper_steps_per_s"] = r.paper_steps_per_s ? nlohmann::json(*r.paper_steps_per_s) : nlohmann::json(nullptr);
    if (r.action_repeat > 0) {
      row["action_repeat"] = r.action_repeat;
      row["solver_iterations"] = r.solver_iterations;
      row["ik_iterations"] = r.ik_iterations;
    }
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

// The rows of one env and mode: ground truth has no image (one row of size 0); raw pixels one row
// per image size and channel choice.
std::vector<bench::Case> cases_of(const EnvEntry& entry, const std::string& mode, const BenchFpsOptions& o) {
  if (mode != "raw_pixels") return {{&entry, mode, 0, "rgb", o.settings}};
  const std::vector<std::string> channels = o.image_channels.empty() ? std::vector<std::string>{"rgb"} : o.image_channels;
  std::vector<bench::Case> cases;
  for (int size : pixel_sizes(o))
    for (const std::string& c : channels) cases.push_back({&entry, mode, size, c, o.settings});
  return cases;
}

bool wanted(const std::vector<std::string>& filter, const std::string& value) {
  return filter.empty() || std::find(filter.begin(), filter.end(), value) != filter.end();
}

// Every row the options ask for: env x mode (x image size), or with --paper env x mode x
// {paper preset, default}.
std::vector<BenchRow> measure(const BenchFpsOptions& o) {
  std::vector<BenchRow> rows;
  for (const auto& entry : env_registry()) {
    // Presets: the paper's robot tasks (the generic reach env has none).
    if (!wanted(o.envs, entry.name) || (o.paper && !std::filesystem::exists(paper_preset_path(entry.name, "ground_truth"))))
      continue;
    for (std::string mode : {"ground_truth", "raw_pixels"}) {
      if (!wanted(o.modes, mode) || (mode == "raw_pixels" && !entry.supports_pixels)) continue;
      if (o.paper) {
        const EnvConfig preset = paper_preset(entry.name, mode);
        const int size = mode == "raw_pixels" ? preset.image_width : 0;
        if (auto row = bench_row(preset, "paper", o)) rows.push_back(std::move(*row));
        if (auto row = bench_row(bench::row_config(entry.name, mode, size), "default", o)) rows.push_back(std::move(*row));
        continue;
      }
      // Ground truth has no image: one row with size 0.
      for (const bench::Case& c : cases_of(entry, mode, o))
        if (auto row = bench_row(bench::case_config(c), "default", o))
          rows.push_back(std::move(*row));
    }
  }
  return rows;
}

// `--threads N` / `--scaling`: the env x mode (x image size) cases, measured on a VecEnv.
int threads_command(const BenchFpsOptions& o) {
  if (o.paper) throw Error("bench-fps: --paper does not combine with --threads/--scaling");
  std::vector<bench::Case> cases;
  for (const auto& entry : env_registry()) {
    if (!wanted(o.envs, entry.name)) continue;
    for (std::string mode : {"ground_truth", "raw_pixels"}) {
      if (!wanted(o.modes, mode) || (mode == "raw_pixels" && !entry.supports_pixels)) continue;
      for (bench::Case& c : cases_of(entry, mode, o)) cases.push_back(std::move(c));
    }
  }
  if (cases.empty()) throw Error("bench-fps: nothing to measure for the given --env/--mode");
  return bench::threads_command(cases, o);
}

}  // namespace

namespace bench {

EnvConfig row_config(const std::string& env, const std::string& mode, int image_size, const std::string& image_channels) {
  EnvConfig config = default_env_config(env);
  config.observation = mode == "raw_pixels" ? ObservationMode::RawPixels : ObservationMode::GroundTruth;
  if (image_size > 0) config.image_width = config.image_height = image_size;
  if (config.observation == ObservationMode::RawPixels) config.image_channels = image_channels;
  return config;
}

EnvConfig with_settings(const EnvConfig& config, const std::vector<std::string>& settings) {
  if (settings.empty()) return config;
  nlohmann::json env = to_json(config);
  for (const std::string& setting : settings) {
    const auto eq = setting.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error("bench-fps: --set: expected KEY=VALUE (an env key, e.g. substeps=5), got \"" + setting + "\"");
    const std::string key = setting.substr(0, eq), text = setting.substr(eq + 1);
    // JSON where the text is JSON (5, true, [0.7, 1.3], {"action_latency": 2}), else the text itself.
    nlohmann::json value = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (value.is_discarded() || value.is_string()) value = json_from_option(text);
    env[key] = std::move(value);
  }
  ConfigReader reader(env, "bench-fps --set", "env");
  return read_env_config(reader);
}

void announce(const Case& c) {
  std::fprintf(stderr, "bench-fps: %s / %s", c.entry->name.c_str(), c.mode.c_str());
  if (c.image_size > 0) std::fprintf(stderr, " %s", image_label(c.image_size, c.image_channels).c_str());
  std::fprintf(stderr, " ...\n");
}

}  // namespace bench

int bench_fps_command(const BenchFpsOptions& o) {
  for (const auto& name : o.envs) (void)env_entry(name);  // the "unknown environment" error with the known names
  if (o.paper && !o.settings.empty()) throw Error("bench-fps: --set does not combine with --paper (its presets are fixed)");
  if (o.threads > 0 || o.scaling) return threads_command(o);
  const std::vector<BenchRow> rows = measure(o);
  if (rows.empty()) throw Error("bench-fps: nothing to measure for the given --env/--mode");
  print_table(table_stream(o.json_path), rows, o);
  write_bench_json(o.json_path, to_json(rows, o));
  return 0;
}

}  // namespace rdsim
