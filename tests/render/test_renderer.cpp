#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/render/renderer.hpp"
#include "render_test_util.hpp"

using Catch::Matchers::Contains;
using namespace rdsim;
using namespace rdsim::test;

namespace {

const Eigen::Vector4f kRed(0.9f, 0.05f, 0.05f, 1.0f);

std::vector<std::uint8_t> draw(Renderer& r, const Scene& s, const Camera& c) {
  std::vector<std::uint8_t> img(static_cast<size_t>(r.width() * r.height() * 3));
  r.render(s, c, img.data());
  return img;
}

Scene red_sphere_at(const Eigen::Vector3f& p, float radius = 0.3f) {
  Scene s;
  DrawItem ball = make_sphere(radius, kRed);
  ball.pose = at_position(p);
  s.add(ball);
  return s;
}

// Mean pixel position of the red pixels, as (col, row).
Eigen::Vector2f red_centroid(const std::vector<std::uint8_t>& img, int w, int h) {
  Eigen::Vector2f sum = Eigen::Vector2f::Zero();
  int n = 0;
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col)
      if (reddish(at(img, w, {col, row}))) {
        sum += Eigen::Vector2f(static_cast<float>(col), static_cast<float>(row));
        ++n;
      }
  REQUIRE(n > 0);
  return sum / static_cast<float>(n);
}

bool is_background(Rgb c, const Scene& s) {
  auto byte = [](float v) { return static_cast<int>(v * 255.0f + 0.5f); };
  return std::abs(c.r - byte(s.background.x())) <= 1 && std::abs(c.g - byte(s.background.y())) <= 1 &&
         std::abs(c.b - byte(s.background.z())) <= 1;
}

}  // namespace

TEST_CASE("make_renderer knows osmesa and rejects unknown backends and sizes", "[render]") {
  const auto names = renderer_backends();
  REQUIRE(std::find(names.begin(), names.end(), "osmesa") != names.end());
  auto r = make_renderer("osmesa", 40, 30);
  CHECK(r->width() == 40);
  CHECK(r->height() == 30);
  CHECK(r->backend() == "osmesa");
  CHECK_FALSE(r->device().empty());
  CHECK_THROWS_WITH(make_renderer("vulkan", 8, 8), Contains("vulkan") && Contains("osmesa"));
  CHECK_THROWS_AS(make_renderer("osmesa", 0, 8), Error);
  CHECK_THROWS_AS(make_renderer("osmesa", 8, 5000), Error);
}

TEST_CASE("render writes exactly height x width x 3 bytes", "[render]") {
  const int w = 37, h = 23;  // odd width: rows are not 4-byte aligned
  auto r = make_renderer("osmesa", w, h);
  const size_t n = static_cast<size_t>(w * h * 3);
  std::vector<std::uint8_t> buf(n + 64, 0xAB);
  r->render(red_sphere_at({0, 0, 0}), side_camera(w, h), buf.data());
  for (size_t i = n; i < buf.size(); ++i) REQUIRE(buf[i] == 0xAB);
  size_t untouched = 0;
  for (size_t i = 0; i < n; ++i) untouched += buf[i] == 0xAB;
  CHECK(untouched < n / 10);
}

TEST_CASE("a red sphere in front of the camera is red in the middle, background at the corners",
          "[render]") {
  const int w = 64, h = 64;
  auto r = make_renderer("osmesa", w, h);
  const Scene s = red_sphere_at({0, 0, 0});
  const auto img = draw(*r, s, side_camera(w, h));
  CHECK(reddish(at(img, w, {w / 2, h / 2})));
  for (Pixel corner : {Pixel{0, 0}, Pixel{w - 1, 0}, Pixel{0, h - 1}, Pixel{w - 1, h - 1}})
    CHECK(is_background(at(img, w, corner), s));
  // The sphere covers about the disc the camera model predicts: radius 0.3 at 2 m.
  const Pixel rim = project(side_camera(w, h), {0, 0.3f, 0});
  CHECK(reddish(at(img, w, {rim.col - 2, h / 2})));
  CHECK_FALSE(reddish(at(img, w, {rim.col + 2, h / 2})));
}

TEST_CASE("moving an item moves its pixels the way the camera sees it", "[render]") {
  const int w = 64, h = 48;
  auto r = make_renderer("osmesa", w, h);
  const Camera cam = side_camera(w, h);
  const auto centre = red_centroid(draw(*r, red_sphere_at({0, 0, 0}, 0.15f), cam), w, h);
  const auto right = red_centroid(draw(*r, red_sphere_at({0, 0.4f, 0}, 0.15f), cam), w, h);
  const auto up = red_centroid(draw(*r, red_sphere_at({0, 0, 0.4f}, 0.15f), cam), w, h);
  // Camera on +x looking at the origin with z up: world +y is image right, +z is image up (row 0
  // is the top row).
  CHECK(right.x() > centre.x() + 5.0f);
  CHECK(std::abs(right.y() - centre.y()) < 1.0f);
  CHECK(up.y() < centre.y() - 5.0f);
  CHECK(std::abs(up.x() - centre.x()) < 1.0f);
  const Pixel predicted = project(cam, {0, 0.4f, 0});
  CHECK(std::abs(right.x() - static_cast<float>(predicted.col)) < 1.5f);

  // set_pose moves an item in place: the pixels where it was become background.
  Scene s = red_sphere_at({0, 0, 0}, 0.15f);
  const auto before = draw(*r, s, cam);
  s.set_pose(0, at_position({0, -0.5f, 0}));
  const auto after = draw(*r, s, cam);
  CHECK(before != after);
  CHECK(reddish(at(before, w, {w / 2, h / 2})));
  CHECK(is_background(at(after, w, {w / 2, h / 2}), s));
  CHECK_THROWS_AS(s.set_pose(1, Eigen::Isometry3f::Identity()), std::out_of_range);
}

TEST_CASE("rendering is deterministic, across frames and across renderers", "[render]") {
  const Scene s = workspace_scene();
  const Camera cam = make_orbit_camera(test::paper_main_view(), 64, 64);
  auto a = make_renderer("osmesa", 64, 64);
  const auto first = draw(*a, s, cam);
  CHECK(draw(*a, s, cam) == first);
  auto b = make_renderer("osmesa", 64, 64);
  CHECK(draw(*b, s, cam) == first);
  CHECK(draw(*a, s, cam) == first);
}

TEST_CASE("two renderers of different sizes work side by side", "[render]") {
  auto small = make_renderer("osmesa", 32, 24);
  const Scene s = red_sphere_at({0, 0, 0});
  const auto small_alone = draw(*small, s, side_camera(32, 24));
  auto big = make_renderer("osmesa", 96, 80);
  const auto big_img = draw(*big, s, side_camera(96, 80));
  CHECK(reddish(at(big_img, 96, {48, 40})));
  CHECK(is_background(at(big_img, 96, {0, 0}), s));
  // Interleaving must not leak one renderer's size or buffer into the other.
  CHECK(draw(*small, s, side_camera(32, 24)) == small_alone);
  CHECK(draw(*big, s, side_camera(96, 80)) == big_img);
  CHECK_THROWS_WITH(small->render(s, side_camera(96, 80), nullptr), Contains("96x80"));
}

TEST_CASE("every shape kind is drawn with its documented size", "[render]") {
  const int w = 96, h = 96;
  auto r = make_renderer("osmesa", w, h);
  const Camera cam = side_camera(w, h, 1.5f);
  auto coloured_at = [&](const DrawItem& item, const Eigen::Vector3f& world) {
    Scene s;
    s.add(item);
    return reddish(at(draw(*r, s, cam), w, project(cam, world)));
  };
  // Box half extents (0.1, 0.2, 0.3): y reaches 0.2, z reaches 0.3.
  const DrawItem box = make_box({0.1f, 0.2f, 0.3f}, kRed);
  CHECK(coloured_at(box, {0, 0.17f, 0.27f}));
  CHECK_FALSE(coloured_at(box, {0, 0.25f, 0}));
  CHECK_FALSE(coloured_at(box, {0, 0, 0.36f}));
  // Cylinder radius 0.1, full length 0.6 along z.
  const DrawItem cyl = make_cylinder(0.1f, 0.6f, kRed);
  CHECK(coloured_at(cyl, {0, 0.0f, 0.27f}));
  CHECK_FALSE(coloured_at(cyl, {0, 0.0f, 0.36f}));
  CHECK_FALSE(coloured_at(cyl, {0, 0.15f, 0}));
  // Capsule radius 0.1 with 0.6 between cap centres: the caps reach z = 0.4.
  const DrawItem cap = make_capsule(0.1f, 0.6f, kRed);
  CHECK(coloured_at(cap, {0, 0.0f, 0.36f}));
  CHECK(coloured_at(cap, {0, 0.0f, -0.36f}));
  CHECK_FALSE(coloured_at(cap, {0, 0.0f, 0.45f}));
  CHECK_FALSE(coloured_at(cap, {0, 0.0f, -0.45f}));
  // Sphere radius 0.25.
  const DrawItem ball = make_sphere(0.25f, kRed);
  CHECK(coloured_at(ball, {0, 0.21f, 0}));
  CHECK_FALSE(coloured_at(ball, {0, 0.29f, 0}));
  // A rotated cylinder lies along its pose's z axis.
  DrawItem lying = cyl;
  lying.pose.linear() = Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitX())
                            .toRotationMatrix();
  CHECK(coloured_at(lying, {0, 0.27f, 0}));
  CHECK_FALSE(coloured_at(lying, {0, 0, 0.2f}));
  // alpha == 0 hides an item.
  DrawItem hidden = ball;
  hidden.rgba[3] = 0.0f;
  CHECK_FALSE(coloured_at(hidden, {0, 0, 0}));
}

TEST_CASE("an unbounded plane fills the view below the horizon, only from above", "[render]") {
  const int w = 48, h = 48;
  auto r = make_renderer("osmesa", w, h);
  Camera cam = side_camera(w, h);
  cam.eye.z() = 0.5f;
  Scene s;
  DrawItem floor = make_plane(0, 0, kRed);
  s.add(floor);
  auto img = draw(*r, s, cam);
  CHECK(reddish(at(img, w, {w / 2, h - 1})));
  CHECK(reddish(at(img, w, {0, h - 1})));
  CHECK(is_background(at(img, w, {w / 2, 0}), s));
  // From below the plane is culled, like a ground that cannot be seen through from underneath.
  cam.eye.z() = -0.5f;
  img = draw(*r, s, cam);
  CHECK(is_background(at(img, w, {w / 2, 0}), s));
  CHECK(is_background(at(img, w, {w / 2, h - 1}), s));
}

TEST_CASE("the lit side of a sphere is brighter than the side facing away", "[render]") {
  const int w = 64, h = 64;
  auto r = make_renderer("osmesa", w, h);
  const Camera cam = side_camera(w, h);
  Scene s = red_sphere_at({0, 0, 0}, 0.5f);
  s.light_direction = {0.0f, -1.0f, 0.0f};  // light travels towards -y: lights the +y side
  const auto img = draw(*r, s, cam);
  const int lit = at(img, w, project(cam, {0.2f, 0.4f, 0})).r;
  const int dark = at(img, w, project(cam, {0.2f, -0.4f, 0})).r;
  CHECK(lit > dark + 60);
  // The dark side still gets the ambient term.
  CHECK(dark > 30);
}

TEST_CASE("a mismatched or broken camera is refused with a clear error", "[render]") {
  auto r = make_renderer("osmesa", 16, 16);
  std::vector<std::uint8_t> img(16 * 16 * 3);
  Camera c = side_camera(16, 16);
  c.fov_deg = 200.0f;
  CHECK_THROWS_WITH(r->render(Scene{}, c, img.data()), Contains("fov_deg"));
  CHECK_THROWS_WITH(r->render(Scene{}, side_camera(16, 8), img.data()), Contains("16x16"));
}
