#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// The `rdsim` subcommands. src/main.cpp parses the command line into these option structs;
// each command lives in its own file under src/app/ and returns the process exit code.
// Bad input is reported by throwing rdsim::Error.
namespace rdsim {

struct TrainOptions {
  std::string config_path;
  std::string resume_dir;                   // continue from this run folder's last checkpoint
  std::optional<std::uint64_t> seed;        // overrides the config's seed
  std::optional<long long> timesteps;       // overrides the config's total_timesteps
  std::string log_dir;                      // overrides the config's log_dir
  bool quiet = false;                       // no progress line
};
int train_command(const TrainOptions& options);

struct ReplayOptions {
  std::string model_path;
  int episodes = 10;
  std::optional<std::uint64_t> seed;  // default: the model's training seed
  bool stochastic = false;            // sample actions instead of taking the most likely one
  std::string record_dir;             // write every frame as PNG here (empty: no recording)
};
int replay_command(const ReplayOptions& options);

struct BenchFpsOptions {
  std::vector<std::string> envs;        // empty: every registered env
  std::vector<std::string> modes;       // "ground_truth", "raw_pixels"; empty: all supported
  std::vector<int> image_sizes;         // raw_pixels rows: one per square size; empty: 64 and 224
  int runs = 5;                         // the median of this many runs is reported
  long long steps = 20000;              // env steps per run
  std::string json_path;                // "-" for stdout; empty: no JSON
};
int bench_fps_command(const BenchFpsOptions& options);

int envs_command();

// `rdsim render`: the image an env's agent sees after reset (raw-pixel observation) as a PNG.
struct RenderOptions {
  std::string env;                 // registry name
  std::string out_path;            // PNG file to write
  int view = 1;                    // 1 = main camera, 2 = the second (multi_view) camera
  int width = 64;                  // image size (env.image_width / image_height)
  int height = 64;
  std::uint64_t seed = 0;          // reset seed
  bool random_target = false;      // env.random_target, so the seed moves the target
};
int render_command(const RenderOptions& options);

}  // namespace rdsim
