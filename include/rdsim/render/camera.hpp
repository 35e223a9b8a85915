#pragma once
#include <Eigen/Geometry>

namespace rdsim {

// A pinhole camera as plain data. World frame is z-up (Bullet/URDF convention).
// width/height are the image size in pixels; they must match the Renderer that draws with it.
struct Camera {
  Eigen::Vector3f eye{1.0f, -1.0f, 1.0f};
  Eigen::Vector3f target{0.0f, 0.0f, 0.0f};
  Eigen::Vector3f up{0.0f, 0.0f, 1.0f};
  float fov_deg = 60.0f;  // vertical field of view
  float znear = 0.1f;     // clip planes, metres from the eye
  float zfar = 100.0f;
  int width = 64;
  int height = 64;
};

// PyBullet-style orbit parameters (computeViewMatrixFromYawPitchRoll with upAxisIndex = 2 and
// computeProjectionMatrixFOV), because the paper gives its cameras this way. Each task keeps its
// cameras in its own file (envs/reaching/jaka_button.cpp reach_main_view, ...).
struct OrbitView {
  Eigen::Vector3f target{0.0f, 0.0f, 0.0f};
  float distance = 1.0f;  // metres from target to eye
  float yaw_deg = 0.0f;   // about world z; 0 puts the eye on the -y side of the target
  float pitch_deg = 0.0f; // negative looks down on the target
  float roll_deg = 0.0f;
  float fov_deg = 60.0f;
  float znear = 0.1f;
  float zfar = 100.0f;
};

Camera make_orbit_camera(const OrbitView& view, int width, int height);

// rdsim::Error naming the bad field when the camera cannot be drawn (non-positive size, fov
// outside (0, 180), znear <= 0 or zfar <= znear, eye on the target, up along the view line).
void check_camera(const Camera& camera);

// OpenGL conventions (right-handed eye space looking down -z, clip z in [-w, w]).
Eigen::Matrix4f view_matrix(const Camera& camera);
Eigen::Matrix4f projection_matrix(const Camera& camera);

}  // namespace rdsim
