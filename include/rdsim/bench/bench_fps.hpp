#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// `rdsim bench-fps`: the paper's Table 3, env steps per second (src/bench/bench_fps.cpp).
namespace rdsim {

struct BenchFpsOptions {
  std::vector<std::string> envs;        // empty: every registered env
  std::vector<std::string> modes;       // "ground_truth", "raw_pixels"; empty: all supported
  std::vector<int> image_sizes;         // raw_pixels rows: one per square size; empty: 64 and 224
  std::vector<std::string> image_channels;  // raw_pixels rows: one per EnvConfig::image_channels; empty: rgb
  int runs = 5;                         // the median of this many runs is reported
  long long steps = 20000;              // env steps per run
  std::string json_path;                // "-" for stdout; empty: no JSON
  // "KEY=VALUE" env keys set on every measured env (--set substeps=5): VALUE a number, true/false,
  // a JSON list or object, or else text; checked as a config file's env keys are.
  std::vector<std::string> settings;
  // Threaded mode (`--threads N` or `--scaling`): a VecEnv of num_envs envs stepped by 1 and N
  // threads (or 1, 2, 4, ... up to every core), total env steps/s and the speed-up over one
  // thread, measured in the same run, and the pool's overhead per env step against a plain loop.
  int threads = 0;                      // N; 0: not asked
  bool scaling = false;
  int num_envs = 0;                     // 0: 4 per thread of the largest count
  // The like-for-like Table 3: for each reaching env, ground truth and 224x224 pixels, its paper
  // preset (configs/paper/<env>.json, <env>_pixels.json: the original's per-step work) next to
  // its defaults at the same image size. --env and --mode filter; --image-size does not apply.
  bool paper = false;
};
int bench_fps_command(const BenchFpsOptions& options);

}  // namespace rdsim
