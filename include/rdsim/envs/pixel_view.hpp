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
// (created here, once per env, reused every step) from one camera, or two stacked as 6 channels
// (EnvConfig::multi_view). Image size from EnvConfig::image_width/height (default 64x64).
namespace rdsim {

class PixelView {
public:
  // `views`: the env's main and second camera; only the first is used without multi_view.
  // rdsim::Error naming env.image_width/height for sizes outside 1..4096.
  PixelView(const ReachTask& task, const EnvConfig& config, const OrbitView& main_view, const OrbitView& second_view);

  // UInt8 {height, width, 3} (6 channels with multi_view).
  const ObservationSpace& space() const { return space_; }
  int views() const { return static_cast<int>(cameras_.size()); }

  // Renders the task's current state into `pixels` (resized to space().size(), HWC).
  void render(const ReachTask& task, std::vector<std::uint8_t>& pixels);
  // The same into caller memory of space().size() bytes (a VecEnv batch column).
  void render(const ReachTask& task, std::uint8_t* pixels);

private:
  RobotScene scene_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<Camera> cameras_;
  ObservationSpace space_;
  std::vector<std::uint8_t> frame_;  // one view, RGB, for multi-view interleaving
};

}  // namespace rdsim
