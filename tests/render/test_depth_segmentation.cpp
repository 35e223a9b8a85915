// Depth and segmentation images (RenderTargets): depth against the analytic distance along the
// view axis at every pixel, segment ids exactly where their items are seen, and colour unchanged
// by reading them in the same pass.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <vector>

#include "rdsim/render/renderer.hpp"
#include "render_test_util.hpp"

using namespace rdsim;

namespace {

// Looking down at the floor (z = 0) at 42 degrees, the top rows meeting it about 5 m away.
Camera floor_camera(int w, int h) {
  Camera c;
  c.eye = {0.0f, -1.0f, 1.2f};
  c.target = {0.0f, 0.3f, 0.0f};
  c.width = w;
  c.height = h;
  return c;
}

// Where the ray through the centre of pixel (col, row) meets the plane z = 0, as metres along
// the view axis (eye space -z), from the camera's own view matrix.
double floor_depth(const Camera& c, int col, int row) {
  const double t = std::tan(0.5 * c.fov_deg * M_PI / 180.0);
  const double aspect = static_cast<double>(c.width) / c.height;
  const double x = (2.0 * (col + 0.5) / c.width - 1.0) * t * aspect;
  const double y = (1.0 - 2.0 * (row + 0.5) / c.height) * t;
  const Eigen::Matrix3d to_eye = view_matrix(c).topLeftCorner<3, 3>().cast<double>();
  const Eigen::Vector3d direction = to_eye.transpose() * Eigen::Vector3d(x, y, -1.0);  // 1 m along the axis
  return -static_cast<double>(c.eye.z()) / direction.z();
}

}  // namespace

TEST_CASE("renderer: depth of a floor equals the analytic distance along the view axis within 1 mm", "[render][depth]") {
  const int w = 48, h = 40;
  auto r = make_renderer("osmesa", w, h);
  Scene s;
  s.add(make_plane(0.0f, 0.0f, {0.5f, 0.5f, 0.5f, 1.0f}));
  const Camera c = floor_camera(w, h);
  std::vector<float> depth(static_cast<std::size_t>(w * h), -1.0f);
  r->render(s, c, RenderTargets{.depth = depth.data()});
  double worst = 0.0;
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col)
      worst = std::max(worst, std::abs(depth[static_cast<std::size_t>(row * w + col)] - floor_depth(c, col, row)));
  INFO("largest error " << worst << " m; top-left depth " << depth[0] << " m");
  CHECK(worst <= 1e-3);
  CHECK(depth[0] > 4.0f);  // the far rows are metres away: the check covers the range
}

TEST_CASE("renderer: where nothing is drawn the depth is the camera's zfar", "[render][depth]") {
  auto r = make_renderer("osmesa", 16, 16);
  Camera c = floor_camera(16, 16);
  c.zfar = 7.5f;
  std::vector<float> depth(256, 0.0f);
  r->render(Scene{}, c, RenderTargets{.depth = depth.data()});
  for (float d : depth) CHECK(d == Approx(7.5f).epsilon(1e-6));
}

TEST_CASE("renderer: every item's segment id shows exactly where it is seen, in the same pass as colour and depth",
          "[render][segmentation]") {
  const int w = 64, h = 48;
  auto r = make_renderer("osmesa", w, h);
  Scene s;
  DrawItem floor = make_plane(1.0f, 1.0f, {0.5f, 0.5f, 0.5f, 1.0f});
  floor.segment = 200;
  s.add(floor);
  DrawItem box = make_box({0.1f, 0.1f, 0.1f}, {0.1f, 0.8f, 0.1f, 1.0f});
  box.pose.translation() = Eigen::Vector3f(-0.25f, 0.3f, 0.1f);
  box.segment = 7;
  s.add(box);
  DrawItem ball = make_sphere(0.12f, {0.9f, 0.05f, 0.05f, 1.0f});
  ball.pose.translation() = Eigen::Vector3f(0.25f, 0.3f, 0.12f);
  ball.segment = 42;
  s.add(ball);
  DrawItem hidden = make_sphere(0.05f, {0.1f, 0.1f, 0.9f, 1.0f});
  hidden.pose.translation() = Eigen::Vector3f(0.25f, 0.45f, 0.12f);  // behind the red ball
  hidden.segment = 99;
  s.add(hidden);
  Camera c = floor_camera(w, h);
  c.eye = {0.0f, -0.8f, 0.5f};

  const auto n = static_cast<std::size_t>(w * h);
  std::vector<std::uint8_t> plain(3 * n), rgb(3 * n), seg(n);
  std::vector<float> depth(n);
  r->render(s, c, plain.data());
  r->render(s, c, RenderTargets{.rgb = rgb.data(), .depth = depth.data(), .segmentation = seg.data()});
  CHECK(rgb == plain);  // reading ids and depth changes no colour

  std::set<int> seen(seg.begin(), seg.end());
  CHECK(seen == std::set<int>{0, 7, 42, 200});  // the floor ends: background (0) beyond it; 99 is hidden
  // Each id's pixels have its item's colour (lit, so compare the dominant channel) and vice versa.
  int ball_pixels = 0, box_pixels = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int red = rgb[3 * i], green = rgb[3 * i + 1], blue = rgb[3 * i + 2];
    if (seg[i] == 42) {
      ++ball_pixels;
      CHECK(red > 3 * std::max(green, blue));
    }
    if (seg[i] == 7) {
      ++box_pixels;
      CHECK(green > 3 * std::max(red, blue));
    }
    if (seg[i] == 0) CHECK(depth[i] == Approx(c.zfar));
    if (seg[i] != 0) CHECK(depth[i] < 3.0f);
  }
  CHECK(ball_pixels > 20);
  CHECK(box_pixels > 20);
  // The ball's centre pixel sees its front surface, on the ray to the centre 0.12 m short of it:
  // along the view axis, the centre's depth times (distance - radius) / distance.
  const test::Pixel centre = test::project(c, ball.pose.translation());
  const std::size_t at = static_cast<std::size_t>(centre.row * w + centre.col);
  CHECK(seg[at] == 42);
  const Eigen::Vector3f eye_space = (view_matrix(c) * ball.pose.translation().homogeneous()).head<3>();
  const float front = -eye_space.z() * (eye_space.norm() - 0.12f) / eye_space.norm();
  // The sphere is drawn as 8 x 12 flat facets, whose middles lie up to about 1 cm inside it.
  CHECK(depth[at] >= front - 0.002f);
  CHECK(depth[at] <= front + 0.015f);
}

TEST_CASE("renderer: depth and segmentation alone, and the same frame twice", "[render][segmentation]") {
  auto r = make_renderer("osmesa", 24, 20);
  Scene s;
  DrawItem ball = make_sphere(0.3f, {0.2f, 0.3f, 0.9f, 1.0f});
  ball.segment = 255;
  s.add(ball);
  const Camera c = floor_camera(24, 20);
  Camera toward = c;
  toward.target = {0.0f, 0.0f, 0.0f};
  std::vector<std::uint8_t> a(480), b(480);
  std::vector<float> da(480), db(480);
  r->render(s, toward, RenderTargets{.segmentation = a.data()});
  r->render(s, toward, RenderTargets{.depth = da.data(), .segmentation = b.data()});
  r->render(s, toward, RenderTargets{.depth = db.data()});
  CHECK(a == b);
  CHECK(da == db);
  CHECK(std::count(a.begin(), a.end(), 255) > 30);
}
