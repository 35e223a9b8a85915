#include "rdsim/render/camera.hpp"

#include <cmath>
#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {
constexpr float kDegToRad = static_cast<float>(M_PI / 180.0);
}

Camera make_orbit_camera(const OrbitView& view, int width, int height) {
  // Same construction as PyBullet's z-up orbit camera: start behind the target on -y with z up,
  // then rotate by R = Rz(yaw) * Ry(roll) * Rx(pitch), so the paper's numbers reproduce its views.
  const Eigen::Matrix3f rot =
      (Eigen::AngleAxisf(view.yaw_deg * kDegToRad, Eigen::Vector3f::UnitZ()) *
       Eigen::AngleAxisf(view.roll_deg * kDegToRad, Eigen::Vector3f::UnitY()) *
       Eigen::AngleAxisf(view.pitch_deg * kDegToRad, Eigen::Vector3f::UnitX()))
          .toRotationMatrix();
  Camera camera;
  camera.target = view.target;
  camera.eye = view.target + rot * Eigen::Vector3f(0.0f, -view.distance, 0.0f);
  camera.up = rot * Eigen::Vector3f::UnitZ();
  camera.fov_deg = view.fov_deg;
  camera.znear = view.znear;
  camera.zfar = view.zfar;
  camera.width = width;
  camera.height = height;
  return camera;
}

void check_camera(const Camera& camera) {
  auto fail = [](const std::string& what) { throw Error("camera: " + what); };
  if (camera.width <= 0 || camera.height <= 0)
    fail("width and height must be positive, got " + std::to_string(camera.width) + "x" +
         std::to_string(camera.height));
  if (!(camera.fov_deg > 0.0f && camera.fov_deg < 180.0f))
    fail("fov_deg must be in (0, 180), got " + std::to_string(camera.fov_deg));
  if (!(camera.znear > 0.0f && camera.zfar > camera.znear))
    fail("need 0 < znear < zfar, got znear " + std::to_string(camera.znear) + ", zfar " +
         std::to_string(camera.zfar));
  const Eigen::Vector3f line = camera.target - camera.eye;
  if (!line.allFinite() || line.norm() < 1e-6f) fail("eye and target must be distinct points");
  const float up_norm = camera.up.norm();
  if (!(up_norm > 1e-6f) || !camera.up.allFinite() ||
      line.normalized().cross(camera.up / up_norm).norm() < 1e-4f)
    fail("up must not be zero or parallel to the line from eye to target");
}

Eigen::Matrix4f view_matrix(const Camera& camera) {
  const Eigen::Vector3f forward = (camera.target - camera.eye).normalized();
  const Eigen::Vector3f side = forward.cross(camera.up).normalized();
  const Eigen::Vector3f up = side.cross(forward);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = side.transpose();
  m.block<1, 3>(1, 0) = up.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -side.dot(camera.eye);
  m(1, 3) = -up.dot(camera.eye);
  m(2, 3) = forward.dot(camera.eye);
  return m;
}

Eigen::Matrix4f projection_matrix(const Camera& camera) {
  const float f = 1.0f / std::tan(0.5f * camera.fov_deg * kDegToRad);
  const float aspect = static_cast<float>(camera.width) / static_cast<float>(camera.height);
  const float n = camera.znear, fa = camera.zfar;
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (fa + n) / (n - fa);
  m(2, 3) = 2.0f * fa * n / (n - fa);
  m(3, 2) = -1.0f;
  return m;
}

}  // namespace rdsim
