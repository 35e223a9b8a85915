#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"
#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/camera.hpp"
#include "rdsim/render/renderer.hpp"

// Raw-pixel observations of a reaching env: its robot and static bodies drawn by ONE renderer
// (created here, once per env, reused every step) from one camera, or two stacked (EnvConfig::
// multi_view). Image size from EnvConfig::image_width/height (default 64x64).
//
// EnvConfig::image_channels chooses what each pixel holds. "rgb": UInt8 r, g, b. Any other: Float32
// channels in the order r, g, b (each in [0, 1]), depth (metres from the camera's plane along its
// axis, the far plane where nothing is drawn), segmentation (RobotScene's id of the body or link
// seen, 0 for the background), those named only; with two cameras the first camera's channels
// come first. All come from one drawing of the scene per camera.
namespace rdsim {

// The images of EnvConfig::image_channels.
struct ImageChannels {
  bool rgb = true, depth = false, segmentation = false;

  explicit ImageChannels(const std::string& name);  // one of image_channel_names()
  int count() const { return (rgb ? 3 : 0) + (depth ? 1 : 0) + (segmentation ? 1 : 0); }
  bool uint8() const { return rgb && !depth && !segmentation; }
};

// The raw-pixel observation space of `config` (what PixelView gives, known without drawing):
// {image_height, image_width, channels x cameras}; Float32 bounds per channel (depth's is the far
// plane, which every env camera has at OrbitView's default).
ObservationSpace pixel_space(const EnvConfig& config);

// A goal env's raw-pixel observation space: `image` (pixel_space's) with the achieved and desired
// goals beside it (vector_size values, their bounds and the parts "achieved_goal", "desired_goal"
// from `ground_truth`, the env's vector space, whose goals come last); `goal` then indexes the
// observation's values (its observation slice: a Float32 image's values, or none).
ObservationSpace pixel_goal_space(const ObservationSpace& image, const ObservationSpace& ground_truth, GoalLayout& goal);

// One episode's changes to a PixelView's drawing (domain randomization, envs/task_randomizer.hpp),
// all relative to the view as built: per camera a shift of its position and target (m, world
// axes), turns of its view direction (rad: yaw about the world's z, then pitch about the camera's
// horizontal axis) and a field-of-view change (deg); every drawn part's r, g, b moved by up to
// colour_noise (uniform, from an Rng seeded with colour_seed, in the scene's part order; clamped
// to [0, 1]); the light direction turned like a camera's view.
struct ViewVariation {
  struct CameraChange {
    Eigen::Vector3f shift = Eigen::Vector3f::Zero();
    float yaw = 0.0f, pitch = 0.0f;  // rad
    float fov = 0.0f;                // deg
  };
  std::vector<CameraChange> cameras;  // one per view (missing ones: no change)
  float colour_noise = 0.0f;
  std::uint64_t colour_seed = 0;
  float light_yaw = 0.0f, light_pitch = 0.0f;  // rad
};

class PixelView {
public:
  // `views`: the env's main and second camera; only the first is used without multi_view.
  // rdsim::Error naming env.image_width/height for sizes outside 1..4096.
  PixelView(const ReachTask& task, const EnvConfig& config, const OrbitView& main_view, const OrbitView& second_view);

  // {height, width, channels x views}: UInt8 for "rgb" (3 or 6 channels), else Float32.
  const ObservationSpace& space() const { return space_; }
  int views() const { return static_cast<int>(cameras_.size()); }

  // Renders the task's current state into `pixels` (resized to space().size(), HWC); "rgb" only.
  void render(const ReachTask& task, std::vector<std::uint8_t>& pixels);
  // The same into caller memory of space().size() bytes or floats (a VecEnv batch column).
  void render(const ReachTask& task, ObservationOut out);

  // Draws from now on with `v` applied to the view as built (replacing any earlier variation).
  void vary(const ViewVariation& v);
  const Camera& camera(int view) const { return cameras_[static_cast<size_t>(view)]; }
  const Scene& scene() const { return scene_.scene; }

private:
  void render_rgb(std::uint8_t* pixels);
  void render_channels(float* values);

  RobotScene scene_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<Camera> cameras_;
  std::vector<Camera> built_cameras_;          // as built (vary() changes copies)
  std::vector<Eigen::Vector4f> built_colours_;  // per scene item, as built
  Eigen::Vector3f built_light_ = Eigen::Vector3f::Zero();
  ImageChannels channels_;
  ObservationSpace space_;
  std::vector<std::uint8_t> frame_;         // one view, RGB, for interleaving
  std::vector<float> depth_;                // one view, metres
  std::vector<std::uint8_t> segmentation_;  // one view, ids
};

}  // namespace rdsim
