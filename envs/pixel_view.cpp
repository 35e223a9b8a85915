#include "rdsim/envs/pixel_view.hpp"

#include <algorithm>
#include <string>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/observation_input.hpp"
#include "rdsim/core/rng.hpp"

namespace rdsim {
namespace {

void check_size(const char* key, int value) {
  if (value < 1 || value > 4096)
    throw Error(std::string("env.") + key + ": expected an integer in [1, 4096], got " + std::to_string(value));
}

}  // namespace

ImageChannels::ImageChannels(const std::string& name)
    : rgb(name.find("rgb") != std::string::npos),
      depth(name.find("depth") != std::string::npos),
      segmentation(name.find("segmentation") != std::string::npos) {
  RDSIM_ASSERT(count() > 0, "image_channels was read from image_channel_names()");
}

PixelView::PixelView(const ReachTask& task, const EnvConfig& config, const OrbitView& main_view,
                     const OrbitView& second_view)
    : channels_(config.image_channels) {
  check_size("image_width", config.image_width);
  check_size("image_height", config.image_height);
  const int w = config.image_width, h = config.image_height;
  add_task_bodies(scene_, task);
  cameras_.push_back(make_orbit_camera(main_view, w, h));
  if (config.multi_view) cameras_.push_back(make_orbit_camera(second_view, w, h));
  for (const Camera& c : cameras_) check_camera(c);
  for (const Camera& c : cameras_) RDSIM_ASSERT(c.zfar == OrbitView{}.zfar, "pixel_space's depth bound is the cameras' far plane");
  renderer_ = make_renderer(config.renderer, w, h);
  space_ = pixel_space(config);
  built_cameras_ = cameras_;
  for (const DrawItem& item : scene_.scene.items) built_colours_.push_back(item.rgba);
  built_light_ = scene_.scene.light_direction;
}

namespace {

// `direction` turned by `yaw` about the world's z, then by `pitch` about its horizontal axis
// (positive raises it).
Eigen::Vector3f turned(const Eigen::Vector3f& direction, float yaw, float pitch) {
  const Eigen::Vector3f d = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()) * direction;
  const Eigen::Vector3f side = d.cross(Eigen::Vector3f::UnitZ());
  if (side.norm() < 1e-6f) return d;  // straight up or down: no horizontal axis to pitch about
  return Eigen::AngleAxisf(pitch, side.normalized()) * d;
}

}  // namespace

void PixelView::vary(const ViewVariation& v) {
  for (size_t c = 0; c < cameras_.size(); ++c) {
    Camera camera = built_cameras_[c];
    if (c < v.cameras.size()) {
      const ViewVariation::CameraChange& change = v.cameras[c];
      const Eigen::Vector3f eye = camera.eye + change.shift;
      camera.target = eye + turned(camera.target - camera.eye, change.yaw, change.pitch);
      camera.eye = eye;
      camera.fov_deg = std::clamp(camera.fov_deg + change.fov, 1.0f, 179.0f);
    }
    cameras_[c] = camera;
  }
  Rng rng(v.colour_seed);
  std::vector<DrawItem>& items = scene_.scene.items;
  for (size_t i = 0; i < items.size(); ++i) {
    items[i].rgba = built_colours_[i];
    if (v.colour_noise <= 0.0f) continue;
    for (int k = 0; k < 3; ++k)
      items[i].rgba[k] = std::clamp(items[i].rgba[k] + static_cast<float>(rng.uniform(-1.0, 1.0)) * v.colour_noise, 0.0f, 1.0f);
  }
  scene_.scene.light_direction = turned(built_light_, v.light_yaw, v.light_pitch);
}

ObservationSpace pixel_space(const EnvConfig& config) {
  const ImageChannels channels(config.image_channels);
  const int views = config.multi_view ? 2 : 1;
  ObservationSpace space;
  space.shape = {config.image_height, config.image_width, channels.count() * views};
  if (channels.uint8()) {
    space.type = ObsType::UInt8;
    return space;
  }
  // Float32 channels: bounds per channel, the same at every pixel.
  space.type = ObsType::Float32;
  std::vector<float> high;
  for (int v = 0; v < views; ++v) {
    if (channels.rgb) high.insert(high.end(), 3, 1.0f);
    if (channels.depth) high.push_back(OrbitView{}.zfar);
    if (channels.segmentation) high.push_back(255.0f);
  }
  const int pixels = config.image_height * config.image_width, stride = static_cast<int>(high.size());
  space.low = Eigen::VectorXf::Zero(space.size());
  space.high.resize(space.size());
  for (int p = 0; p < pixels; ++p)
    for (int k = 0; k < stride; ++k) space.high[p * stride + k] = high[static_cast<size_t>(k)];
  return space;
}

ObservationSpace pixel_goal_space(const ObservationSpace& image, const ObservationSpace& ground_truth, GoalLayout& goal) {
  RDSIM_ASSERT(goal.active() && image.vector_size == 0 && ground_truth.type == ObsType::Float32 &&
                   ground_truth.size() == goal.size(), "a goal env's vector space and its image's");
  const int goals = 2 * goal.goal_size();
  ObservationSpace space = image;
  space.vector_size = goals;
  const int image_values = image.value_count();
  space.low.resize(image_values + goals);
  space.high.resize(image_values + goals);
  space.low.tail(goals) = ground_truth.low.tail(goals);
  space.high.tail(goals) = ground_truth.high.tail(goals);
  if (image_values > 0) {
    space.low.head(image_values) = image.low;
    space.high.head(image_values) = image.high;
  }
  space.parts = {{"achieved_goal", goal.goal_size()}, {"desired_goal", goal.goal_size()}};
  goal.observation = image_values;
  return space;
}

void PixelView::render(const ReachTask& task, std::vector<std::uint8_t>& pixels) {
  RDSIM_ASSERT(space_.type == ObsType::UInt8, "UInt8 frames come from an rgb view");
  pixels.resize(static_cast<size_t>(space_.size()));
  update_poses(scene_, task.world());
  render_rgb(pixels.data());
}

void PixelView::render(const ReachTask& task, ObservationOut out) {
  update_poses(scene_, task.world());
  if (space_.type == ObsType::UInt8)
    render_rgb(out.pixels);
  else
    render_channels(out.values);
}

void PixelView::render_rgb(std::uint8_t* pixels) {
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

// Each camera draws once into the images asked for; each pixel's channels are written in the
// documented order (r, g, b, depth, segmentation; the first camera's first).
void PixelView::render_channels(float* values) {
  const size_t count = static_cast<size_t>(space_.shape[0]) * static_cast<size_t>(space_.shape[1]);
  const size_t stride = static_cast<size_t>(space_.shape[2]);
  frame_.resize(channels_.rgb ? 3 * count : 0);
  depth_.resize(channels_.depth ? count : 0);
  segmentation_.resize(channels_.segmentation ? count : 0);
  const RenderTargets targets{.rgb = channels_.rgb ? frame_.data() : nullptr,
                              .depth = channels_.depth ? depth_.data() : nullptr,
                              .segmentation = channels_.segmentation ? segmentation_.data() : nullptr};
  for (int v = 0; v < views(); ++v) {
    renderer_->render(scene_.scene, cameras_[static_cast<size_t>(v)], targets);
    float* out = values + static_cast<size_t>(v * channels_.count());
    for (size_t p = 0; p < count; ++p, out += stride) {
      float* c = out;
      if (channels_.rgb) {
        // Scaled as the networks scale UInt8 images, so both hold the same colour values.
        for (size_t k = 0; k < 3; ++k) *c++ = static_cast<float>(frame_[3 * p + k]) * pixel_input_scale;
      }
      if (channels_.depth) *c++ = depth_[p];
      if (channels_.segmentation) *c = static_cast<float>(segmentation_[p]);
    }
  }
}

}  // namespace rdsim
