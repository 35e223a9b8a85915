#include "rdsim/envs/pixel_view.hpp"

#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

void check_size(const char* key, int value) {
  if (value < 1 || value > 4096)
    throw Error(std::string("env.") + key + ": expected an integer in [1, 4096], got " + std::to_string(value));
}

}  // namespace

PixelView::PixelView(const ReachTask& task, const EnvConfig& config, const OrbitView& main_view,
                     const OrbitView& second_view) {
  check_size("image_width", config.image_width);
  check_size("image_height", config.image_height);
  const int w = config.image_width, h = config.image_height;
  add_task_bodies(scene_, task);
  cameras_.push_back(make_orbit_camera(main_view, w, h));
  if (config.multi_view) cameras_.push_back(make_orbit_camera(second_view, w, h));
  for (const Camera& c : cameras_) check_camera(c);
  renderer_ = make_renderer(config.renderer, w, h);
  space_.type = ObsType::UInt8;
  space_.shape = {h, w, 3 * views()};
}

void PixelView::render(const ReachTask& task, std::vector<std::uint8_t>& pixels) {
  pixels.resize(static_cast<size_t>(space_.size()));
  render(task, pixels.data());
}

void PixelView::render(const ReachTask& task, std::uint8_t* pixels) {
  update_poses(scene_, task.world());
  if (views() == 1) {
    renderer_->render(scene_.scene, cameras_[0], pixels);
    return;
  }
  // Two cameras: pixel p holds RGB of view 0 then RGB of view 1 (HWC with 6 channels).
  const size_t count = static_cast<size_t>(space_.shape[0]) * static_cast<size_t>(space_.shape[1]);
  frame_.resize(3 * count);
  for (int v = 0; v < views(); ++v) {
    renderer_->render(scene_.scene, cameras_[static_cast<size_t>(v)], frame_.data());
    std::uint8_t* out = pixels + 3 * v;
    for (size_t p = 0; p < count; ++p) {
      out[6 * p] = frame_[3 * p];
      out[6 * p + 1] = frame_[3 * p + 1];
      out[6 * p + 2] = frame_[3 * p + 2];
    }
  }
}

}  // namespace rdsim
