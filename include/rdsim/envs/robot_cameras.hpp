#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"
#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/camera.hpp"
#include "rdsim/render/renderer.hpp"

// The cameras of a reaching task's robot (RobotControl::camera_image): cameras fixed to robot links
// (first person) or to the world, drawn with the task's robot and static bodies at any size a
// caller asks for.
namespace rdsim {

// A camera fixed to a link, or to the world when `link` is empty. Position and directions are in
// that frame; the image's up is `up` made orthogonal to `forward`.
struct CameraMount {
  std::string name;   // "left_eye", "wrist", ...
  std::string link;   // robot link (URDF name); "" = the world frame
  Eigen::Vector3f position = Eigen::Vector3f::Zero();  // m, in the link frame
  Eigen::Vector3f forward = Eigen::Vector3f::UnitX();  // viewing direction
  Eigen::Vector3f up = Eigen::Vector3f::UnitZ();
  float fov_deg = 60.0f;  // vertical
  float znear = 0.01f;    // m: the camera sits on the robot's surface
};

// The Jaka Zu 7's wrist camera: on the flange, 5 cm off the tool axis (flange -x), looking 25 deg
// off the axis towards that side, fov 90 deg: the point under the tool and the table ahead of it
// (jaka_obstacle's column from its home pose).
CameraMount jaka_wrist_camera();
// The InMoov's eyes: at the front of each eyeball (l_eye / r_eye, 1.6 cm ahead of its centre,
// just clear of the head's face), looking straight ahead (+x of the eye, which the eye pan/tilt
// joints turn), fov 60 deg.
std::vector<CameraMount> inmoov_eye_cameras();
// A camera fixed in the world where `view` puts it (the env's raw-pixel main view), named `name`.
CameraMount world_camera(const std::string& name, const OrbitView& view);

class RobotCameras {
public:
  // rdsim::Error naming the link when a mount's link is not a link of the task's robot.
  RobotCameras(const ReachTask& task, std::vector<CameraMount> mounts, std::string renderer_backend);
  ~RobotCameras();

  int size() const { return static_cast<int>(mounts_.size()); }

  // Draws camera `index` at width x height into `out` (RGB, row 0 at the top). The renderer is made
  // on first use and again when the size changes. rdsim::Error for an unknown index or a size
  // outside 1..RobotControl::max_camera_side.
  void render(const ReachTask& task, int index, int width, int height, Image& out);

private:
  std::vector<CameraMount> mounts_;
  std::vector<int> links_;  // RobotModel link of each mount; -1 for the world
  std::string backend_;
  RobotScene scene_;
  std::unique_ptr<Renderer> renderer_;
};

}  // namespace rdsim
