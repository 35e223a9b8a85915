#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// `rdsim replay`: runs a saved policy in the env rebuilt from its model file (src/app/replay.cpp).
namespace rdsim {

struct ReplayOptions {
  std::string model_path;
  int episodes = 10;
  std::optional<std::uint64_t> seed;  // default: the model's training seed
  bool stochastic = false;            // sample actions instead of taking the most likely one
  std::string record_dir;             // write every frame as PNG here (empty: no recording)
  std::optional<double> max_memory_gb;  // memory limit (training/memory_check.hpp)
  std::string video_path;             // write a video (.mp4 or .gif) with a caption per frame
  int video_fps = 20;
  int frame_every = 1;                // record/film every k-th step (and each episode's first and last)
  int frame_width = 0, frame_height = 0;  // frame size; 0: env.render_width/height of the model's config
  bool remote = false;  // a model trained on remote envs: replay on that server (default: a local env)
};
int replay_command(const ReplayOptions& options);

}  // namespace rdsim
