#include "rdsim/video/frame_capture.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "rdsim/core/error.hpp"
#include "rdsim/render/png.hpp"
#include "rdsim/video/overlay.hpp"

namespace rdsim {

void FrameRecorder::start_episode(int episode) {
  if (!on()) return;
  char name[32];
  std::snprintf(name, sizeof name, "episode_%03d", episode);
  episode_dir_ = (std::filesystem::path(dir_) / name).string();
  std::error_code ec;
  std::filesystem::create_directories(episode_dir_, ec);
  if (ec) throw Error(episode_dir_ + ": cannot create the folder (" + ec.message() + ")");
  frame_ = 0;
}

void FrameRecorder::save(const Image& image) {
  if (!on()) return;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.png", frame_++);
  write_png((std::filesystem::path(episode_dir_) / name).string(), image.width, image.height, 3, image.rgb.data());
  ++total_;
}

FrameCapture::FrameCapture(const FrameCaptureOptions& o, Env& env, int episodes, int width, int height)
    : env_(env), recorder_(o.record_dir), every_(o.frame_every), fps_(o.video_fps), episodes_(episodes) {
  if (!o.video_path.empty()) video_ = open_video(o.video_path, width, height, o.video_fps);
}

void FrameCapture::start_episode(int episode) {
  recorder_.start_episode(episode);
  episode_ = episode;
}

void FrameCapture::capture(long long step, double episode_return, bool success, bool last) {
  if (!on() || (step % every_ != 0 && !last)) return;
  if (!env_.render(frame_)) {
    throw Error("replay: env \"" + env_.spec().env_name + "\" cannot draw frames (--record, --video)");
  }
  recorder_.save(frame_);
  if (!video_) return;
  char line[3][64];
  std::snprintf(line[0], sizeof line[0], "episode %d/%d  step %lld", episode_, episodes_, step);
  std::snprintf(line[1], sizeof line[1], "return %.2f", episode_return);
  std::snprintf(line[2], sizeof line[2], "success: %s", success ? "yes" : "no");
  draw_overlay(frame_, {{line[0]}, {line[1]}, {line[2], success}});
  // An episode's last frame stays half a second, so its outcome can be read.
  for (int k = 0, n = last ? std::max(1, fps_ / 2) : 1; k < n; ++k) video_->add_frame(frame_);
}

void FrameCapture::close() {
  if (video_) video_->close();
}

}  // namespace rdsim
