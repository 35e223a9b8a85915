#pragma once
// What the two bench-fps modes share (src/bench/bench_fps.cpp: one env, one thread;
// src/bench/bench_threads.cpp: a VecEnv on 1..N threads). Private to the bench library.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "rdsim/bench/bench_fps.hpp"
#include "rdsim/bench/bench_run.hpp"
#include "rdsim/envs/registry.hpp"

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/rng.hpp"

namespace rdsim::bench {

using Clock = std::chrono::steady_clock;

using rdsim::median;  // rdsim/bench/bench_run.hpp

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using rdsim::random_action;

// `count` random actions drawn before a clock starts, so that a row measures the env alone.
inline std::vector<Action> random_actions(const ActionSpace& space, std::size_t count, std::uint64_t seed) {
  Rng rng = Rng::derive(seed, 1);
  std::vector<Action> actions;
  actions.reserve(count);
  for (std::size_t i = 0; i < count; ++i) actions.push_back(random_action(space, rng));
  return actions;
}

// One thing to measure: an env in one observation mode (and image size for raw pixels).
struct Case {
  const EnvEntry* entry;
  std::string mode;    // "ground_truth" or "raw_pixels"
  int image_size = 0;  // raw_pixels: square image side; 0 for ground truth
  std::string image_channels = "rgb";  // raw_pixels: EnvConfig::image_channels
  std::vector<std::string> settings;    // BenchFpsOptions::settings
};

// "bench-fps: env / mode WxH ..." on stderr.
void announce(const Case& c);

// `bench-fps --threads N` / `--scaling` (src/bench/bench_threads.cpp).
int threads_command(const std::vector<Case>& cases, const BenchFpsOptions& o);

// The env's defaults with the row's observation mode, square image side (0: ground truth) and
// image channels.
EnvConfig row_config(const std::string& env, const std::string& mode, int image_size,
                     const std::string& image_channels = "rgb");
// `config` with BenchFpsOptions::settings applied (rdsim::Error naming --set and the key for a
// malformed one, or a key or value the env does not take).
EnvConfig with_settings(const EnvConfig& config, const std::vector<std::string>& settings);
// The env config a case measures: row_config with its settings.
inline EnvConfig case_config(const Case& c) {
  return with_settings(row_config(c.entry->name, c.mode, c.image_size, c.image_channels), c.settings);
}

// "64x64", "64x64 rgb_depth" (channels other than rgb), or "-" for ground truth.
inline std::string image_label(int image_size, const std::string& image_channels = "rgb") {
  if (image_size <= 0) return "-";
  const std::string size = std::to_string(image_size) + "x" + std::to_string(image_size);
  return image_channels == "rgb" ? size : size + " " + image_channels;
}

}  // namespace rdsim::bench
