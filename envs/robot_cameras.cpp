#include "rdsim/envs/robot_cameras.hpp"

#include <cmath>

#include "rdsim/core/error.hpp"
#include "rdsim/render/camera.hpp"

namespace rdsim {

CameraMount jaka_wrist_camera() {
  CameraMount m;
  m.name = "wrist";
  m.link = "flange_link";  // z: out of the flange face (the tool axis)
  // Looking straight down the tool axis, the camera saw only the table under the flange (a plain
  // brown square at jaka_obstacle's home, 12 cm above it): tilted 25 deg off the axis towards the
  // flange's -x with a 90 deg field of view (a RealSense-like wide lens), it still sees the point
  // under the tool (jaka_button's button at home) and, ahead, jaka_obstacle's column, which stands
  // between that env's home and its button. The far side is at the top of the image.
  constexpr float tilt = 25.0f * static_cast<float>(M_PI) / 180.0f;
  m.position = Eigen::Vector3f(-0.05f, 0.0f, 0.005f);
  m.forward = Eigen::Vector3f(-std::sin(tilt), 0.0f, std::cos(tilt));
  m.up = Eigen::Vector3f(-std::cos(tilt), 0.0f, -std::sin(tilt));
  m.fov_deg = 90.0f;
  return m;
}

std::vector<CameraMount> inmoov_eye_cameras() {
  std::vector<CameraMount> mounts;
  for (const char* side : {"left", "right"}) {
    CameraMount m;
    m.name = std::string(side) + "_eye";
    m.link = std::string(1, side[0]) + "_eye";  // l_eye, r_eye: +x ahead, z up
    m.position = Eigen::Vector3f(0.016f, 0.0f, 0.0f);
    mounts.push_back(m);
  }
  return mounts;
}

CameraMount world_camera(const std::string& name, const OrbitView& view) {
  const Camera c = make_orbit_camera(view, 1, 1);
  CameraMount m;
  m.name = name;
  m.position = c.eye;
  m.forward = (c.target - c.eye).normalized();
  m.up = c.up;
  m.fov_deg = c.fov_deg;
  m.znear = c.znear;
  return m;
}

RobotCameras::RobotCameras(const ReachTask& task, std::vector<CameraMount> mounts, std::string renderer_backend)
    : mounts_(std::move(mounts)), backend_(std::move(renderer_backend)) {
  for (const CameraMount& m : mounts_) links_.push_back(m.link.empty() ? -1 : task.robot_model().require_link(m.link));
  add_task_bodies(scene_, task);
}

RobotCameras::~RobotCameras() = default;

void RobotCameras::render(const ReachTask& task, int index, int width, int height, Image& out) {
  if (index < 0 || index >= size())
    throw Error("camera " + std::to_string(index) + ": no such camera (this robot has " + std::to_string(size()) + ")");
  const int max = RobotControl::max_camera_side;
  if (width < 1 || width > max || height < 1 || height > max)
    throw Error("camera image size " + std::to_string(width) + "x" + std::to_string(height) + ": expected 1.." +
                std::to_string(max) + " pixels per side");
  const CameraMount& m = mounts_[static_cast<size_t>(index)];
  const int link_index = links_[static_cast<size_t>(index)];
  const Eigen::Isometry3f link = link_index < 0 ? Eigen::Isometry3f::Identity() : task.robot().link_pose(link_index);
  Camera camera;
  camera.eye = link * m.position;
  camera.target = camera.eye + link.linear() * m.forward;
  camera.up = link.linear() * m.up;
  camera.fov_deg = m.fov_deg;
  camera.znear = m.znear;
  camera.width = width;
  camera.height = height;
  if (!renderer_ || renderer_->width() != width || renderer_->height() != height)
    renderer_ = make_renderer(backend_, width, height);
  update_poses(scene_, task.world());
  out.width = width;
  out.height = height;
  out.rgb.resize(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
  renderer_->render(scene_.scene, camera, out.rgb.data());
}

}  // namespace rdsim
