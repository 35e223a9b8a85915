#include <catch2/catch.hpp>
#include <cmath>

#include "rdsim/core/error.hpp"
#include "rdsim/render/camera.hpp"
#include "render_test_util.hpp"

using Catch::Matchers::Contains;
using rdsim::Camera;

namespace {
constexpr float kDeg = static_cast<float>(M_PI / 180.0);

// The orbit offset written out by hand: R = Rz(yaw) Rx(pitch) applied to (0, -d, 0).
Eigen::Vector3f expected_offset(float d, float yaw_deg, float pitch_deg) {
  const float y = yaw_deg * kDeg, p = pitch_deg * kDeg;
  return d * Eigen::Vector3f(std::cos(p) * std::sin(y), -std::cos(p) * std::cos(y), -std::sin(p));
}
}  // namespace

TEST_CASE("orbit camera places the eye like PyBullet's yaw/pitch camera", "[render][camera]") {
  for (const rdsim::OrbitView& v : {rdsim::test::paper_main_view(), rdsim::test::paper_second_view()}) {
    const Camera c = rdsim::make_orbit_camera(v, 64, 48);
    CHECK((c.eye - c.target).norm() == Approx(v.distance).epsilon(1e-5));
    const Eigen::Vector3f want = expected_offset(v.distance, v.yaw_deg, v.pitch_deg);
    CHECK((c.eye - c.target - want).norm() < 1e-5f);
    CHECK(c.eye.z() > c.target.z());  // negative pitch looks down
    CHECK(std::abs(c.up.dot((c.target - c.eye).normalized())) < 1e-5f);
    CHECK(c.width == 64);
    CHECK(c.height == 48);
    CHECK(c.fov_deg == 60.0f);
  }
  rdsim::OrbitView level;
  level.distance = 2.0f;
  const Camera c = rdsim::make_orbit_camera(level, 8, 8);
  CHECK((c.eye - Eigen::Vector3f(0, -2, 0)).norm() < 1e-6f);
  CHECK((c.up - Eigen::Vector3f::UnitZ()).norm() < 1e-6f);
}

TEST_CASE("view and projection matrices follow OpenGL conventions", "[render][camera]") {
  Camera c;
  c.eye = {1.0f, 2.0f, 3.0f};
  c.target = {0.5f, -1.0f, 0.0f};
  c.znear = 0.5f;
  c.zfar = 20.0f;
  const Eigen::Matrix4f view = rdsim::view_matrix(c);
  CHECK((view * c.eye.homogeneous()).head<3>().norm() < 1e-5f);
  const Eigen::Vector3f t = (view * c.target.homogeneous()).head<3>();
  CHECK(t.head<2>().norm() < 1e-5f);
  CHECK(t.z() == Approx(-(c.target - c.eye).norm()));
  CHECK(view.topLeftCorner<3, 3>().determinant() == Approx(1.0f));

  const Eigen::Matrix4f proj = rdsim::projection_matrix(c);
  auto ndc_z = [&](float depth) {
    const Eigen::Vector4f clip = proj * Eigen::Vector4f(0, 0, -depth, 1);
    return clip.z() / clip.w();
  };
  CHECK(ndc_z(c.znear) == Approx(-1.0f));
  CHECK(ndc_z(c.zfar) == Approx(1.0f));
  // A point on the top edge of the vertical field of view lands on ndc y = 1.
  const float half = 0.5f * c.fov_deg * kDeg;
  const Eigen::Vector4f edge = proj * Eigen::Vector4f(0, std::tan(half) * 3.0f, -3.0f, 1);
  CHECK(edge.y() / edge.w() == Approx(1.0f));
}

TEST_CASE("check_camera names the bad field", "[render][camera]") {
  Camera ok;
  CHECK_NOTHROW(rdsim::check_camera(ok));
  Camera c = ok;
  c.fov_deg = 0.0f;
  CHECK_THROWS_WITH(rdsim::check_camera(c), Contains("fov_deg"));
  c = ok;
  c.zfar = c.znear;
  CHECK_THROWS_WITH(rdsim::check_camera(c), Contains("znear"));
  c = ok;
  c.target = c.eye;
  CHECK_THROWS_WITH(rdsim::check_camera(c), Contains("eye and target"));
  c = ok;
  c.up = (c.target - c.eye) * 2.0f;
  CHECK_THROWS_WITH(rdsim::check_camera(c), Contains("up"));
  c = ok;
  c.width = 0;
  CHECK_THROWS_AS(rdsim::check_camera(c), rdsim::Error);
}
