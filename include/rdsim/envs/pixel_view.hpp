#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/reach_task.hpp"
#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/camera.hpp"
#include "rdsim/render/renderer.hpp"

// Raw-pixel observations of a reaching env: its robot and static bodies drawn by ONE renderer
// (created here, once per env, reused every step) from one camera, or two stacked as 6 channels
// (EnvConfig::multi_view). Image size from EnvConfig::image_width/height (default 64x64).
namespace rdsim {

// The paper's two cameras (same yaw, pitch, fov) re-aimed at our layout, where the robot base is
// the world origin on the table top (z = 0) and targets lie around x 0.35..0.65: the paper's
// targets/distances (main: (0.316, -0.2, -0.1), 1.6 m) put the robot in a corner of the image and
// made the button 2-3 pixels wide at 64x64. Main: target (0.32, 0.05, 0.15), 1.0 m, yaw 155, pitch -36.
// Second: target (0.45, 0.1, 0.1), 1.1 m, yaw 32, pitch -13.
OrbitView reach_main_view();
OrbitView reach_second_view();
// jaka_obstacle: reach_main_view() looking down steeper (pitch -60, 1.1 m), because from -36 deg
// the column hides the flange at its home pose beside it; button, column and flange all visible.
OrbitView obstacle_main_view();
// inmoov_tomato (robot at the origin facing +x, tree at (0.65, -0.2), tomatoes at z 1.0..1.4):
// main from the front-left, target (0.4, -0.25, 1.15), 1.2 m, yaw 120, pitch -20 (tree, tomatoes
// and the right arm); second from the robot's right, target (0.35, -0.3, 1.15), 1.1 m, yaw 15,
// pitch -10 (palm and tomatoes side by side). fov 60 like the paper's.
OrbitView inmoov_main_view();
OrbitView inmoov_second_view();

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

private:
  RobotScene scene_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<Camera> cameras_;
  ObservationSpace space_;
  std::vector<std::uint8_t> frame_;  // one view, RGB, for multi-view interleaving
};

}  // namespace rdsim
