#include "rdsim/envs/pixel_view.hpp"

#include <malloc.h>

#include <cstdlib>
#include <string>

#include "rdsim/error.hpp"

namespace rdsim {
namespace {

void check_size(const char* key, int value) {
  if (value < 1 || value > 4096)
    throw Error(std::string("env.") + key + ": expected an integer in [1, 4096], got " + std::to_string(value));
}

// Process-wide settings that make per-step offscreen rendering cheap, applied once before the first
// renderer exists (measured on the 2-core dev box, Release, one thread):
//  - Mesa allocates and frees large scratch buffers on every draw. By default glibc gives the top
//    of the heap back to the OS each time (brk) and faults it back in next frame (perf: 26% of the
//    time in page faults), and mmaps/unmaps buffers above 128 KiB. A 512 MiB trim threshold and the
//    largest mmap threshold keep them in the heap: inmoov_tomato 64x64 render 2,600 -> 500 us per
//    frame; jaka_button 224x224 750 -> 2,300 steps/s.
//  - llvmpipe's rasteriser threads (one per core by default) cost more in hand-offs than they save
//    on images this small, and an env step must stay on one thread: LP_NUM_THREADS=0 draws in the
//    calling thread (jaka_button 64x64: 3,100 -> 11,500 steps/s). A value set by the user wins.
void tune_offscreen_rendering() {
  static const bool once = [] {
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest; the call above froze it at 128 KiB
    setenv("LP_NUM_THREADS", "0", 0);
    return true;
  }();
  (void)once;
}

}  // namespace

OrbitView reach_main_view() {
  OrbitView v = paper_main_view();
  v.target = {0.32f, 0.05f, 0.15f};
  v.distance = 1.0f;
  return v;
}

OrbitView reach_second_view() {
  OrbitView v = paper_second_view();
  v.target = {0.45f, 0.1f, 0.1f};
  v.distance = 1.1f;
  return v;
}

OrbitView obstacle_main_view() {
  OrbitView v = reach_main_view();
  v.distance = 1.1f;
  v.pitch_deg = -60.0f;
  return v;
}

OrbitView inmoov_main_view() {
  OrbitView v;
  v.target = {0.4f, -0.25f, 1.15f};
  v.distance = 1.2f;
  v.yaw_deg = 120.0f;
  v.pitch_deg = -20.0f;
  return v;
}

OrbitView inmoov_second_view() {
  OrbitView v;
  v.target = {0.35f, -0.3f, 1.15f};
  v.distance = 1.1f;
  v.yaw_deg = 15.0f;
  v.pitch_deg = -10.0f;
  return v;
}

PixelView::PixelView(const ReachTask& task, const EnvConfig& config, const OrbitView& main_view,
                     const OrbitView& second_view) {
  check_size("image_width", config.image_width);
  check_size("image_height", config.image_height);
  const int w = config.image_width, h = config.image_height;
  add_robot(scene_, task.robot());
  for (size_t i = 0; i < task.spec().statics.size(); ++i) {
    const int index = static_cast<int>(i);
    add_static_body(scene_, task.world(), task.static_body(index), task.static_model(index));
  }
  cameras_.push_back(make_orbit_camera(main_view, w, h));
  if (config.multi_view) cameras_.push_back(make_orbit_camera(second_view, w, h));
  for (const Camera& c : cameras_) check_camera(c);
  tune_offscreen_rendering();
  renderer_ = make_renderer("osmesa", w, h);
  space_.type = ObsType::UInt8;
  space_.shape = {h, w, 3 * views()};
}

void PixelView::render(const ReachTask& task, std::vector<std::uint8_t>& pixels) {
  update_poses(scene_, task.world());
  pixels.resize(static_cast<size_t>(space_.size()));
  if (views() == 1) {
    renderer_->render(scene_.scene, cameras_[0], pixels.data());
    return;
  }
  // Two cameras: pixel p holds RGB of view 0 then RGB of view 1 (HWC with 6 channels).
  const size_t count = static_cast<size_t>(space_.shape[0]) * static_cast<size_t>(space_.shape[1]);
  frame_.resize(3 * count);
  for (int v = 0; v < views(); ++v) {
    renderer_->render(scene_.scene, cameras_[static_cast<size_t>(v)], frame_.data());
    std::uint8_t* out = pixels.data() + 3 * v;
    for (size_t p = 0; p < count; ++p) {
      out[6 * p] = frame_[3 * p];
      out[6 * p + 1] = frame_[3 * p + 1];
      out[6 * p + 2] = frame_[3 * p + 2];
    }
  }
}

}  // namespace rdsim
