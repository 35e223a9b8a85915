#pragma once
#include <memory>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/video/video_writer.hpp"

// What a replay shows of each step of an env: its frame, as PNG files
// DIR/episode_NNN/frame_NNNN.png and/or a video captioned with episode, step, return and success.
namespace rdsim {

struct FrameCaptureOptions {
  std::string record_dir;  // PNG frames here; empty: none
  std::string video_path;  // .mp4 or .gif; empty: none
  int video_fps = 20;
  int frame_every = 1;     // keep every k-th step's frame (and each episode's first and last)
};

// Writes frames of the episodes being replayed as DIR/episode_NNN/frame_NNNN.png.
class FrameRecorder {
public:
  explicit FrameRecorder(std::string dir) : dir_(std::move(dir)) {}
  bool on() const { return !dir_.empty(); }
  void start_episode(int episode);
  void save(const Image& image);
  long long total() const { return total_; }

private:
  std::string dir_, episode_dir_;
  int frame_ = 0;
  long long total_ = 0;
};

class FrameCapture {
public:
  // `episodes`: how many the replay runs (for the caption); width x height: the env's frames.
  FrameCapture(const FrameCaptureOptions& o, Env& env, int episodes, int width, int height);
  bool on() const { return recorder_.on() || video_; }
  void start_episode(int episode);
  // The state after `step` steps (0: the reset); the last step of an episode is always kept.
  // rdsim::Error when the env cannot draw frames.
  void capture(long long step, double episode_return, bool success, bool last);
  void close();
  long long pictures() const { return recorder_.total(); }
  std::string video_format() const { return video_ ? video_->format() : ""; }

private:
  Env& env_;
  FrameRecorder recorder_;
  std::unique_ptr<VideoWriter> video_;
  Image frame_;
  int every_, fps_, episodes_, episode_ = 0;
};

}  // namespace rdsim
