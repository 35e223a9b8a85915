// Loaded triangle meshes (DrawShape::Mesh): drawn like the unit shapes, in their own colours
// times the item's, with the triangles that face away culled.
#include <catch2/catch.hpp>

#include <cstdint>
#include <memory>
#include <vector>

#include "rdsim/render/renderer.hpp"
#include "render_test_util.hpp"

using namespace rdsim;
using namespace rdsim::test;

namespace {

// The cube [-h, h]^3 with flat faces, counter-clockwise from outside, as a mesh file would give it.
std::shared_ptr<TriangleMesh> cube_mesh(float h) {
  auto m = std::make_shared<TriangleMesh>();
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f}) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero(), u = n, v = n;
      n[axis] = sign;
      u[(axis + 1) % 3] = 1.0f;
      v[(axis + 2) % 3] = sign;
      const auto base = static_cast<std::uint32_t>(m->positions.size());
      for (const Eigen::Vector3f& corner : {Eigen::Vector3f(n - u - v), Eigen::Vector3f(n + u - v), Eigen::Vector3f(n + u + v), Eigen::Vector3f(n - u + v)}) {
        m->positions.push_back(h * corner);
        m->normals.push_back(n);
      }
      m->indices.insert(m->indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  return m;
}

std::vector<std::uint8_t> draw(Renderer& r, const Scene& s, const Camera& c) {
  std::vector<std::uint8_t> img(static_cast<size_t>(r.width() * r.height() * 3));
  r.render(s, c, img.data());
  return img;
}

Camera oblique_camera(int w, int h) {
  Camera c = side_camera(w, h);
  c.eye = {1.6f, 1.0f, 1.2f};  // three faces in view, each lit differently
  return c;
}

}  // namespace

TEST_CASE("a cube mesh draws like the box of the same size, but for a few edge pixels", "[render][mesh]") {
  const int w = 64, h = 64;
  auto r = make_renderer("osmesa", w, h);
  const Eigen::Vector4f red(0.9f, 0.05f, 0.05f, 1.0f);
  Eigen::Isometry3f pose = Eigen::Isometry3f(Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitZ()));
  pose.translation() = Eigen::Vector3f(0.0f, 0.1f, -0.05f);
  Scene box, mesh;
  box.add(make_box(Eigen::Vector3f::Constant(0.3f), red));
  mesh.add(make_mesh(cube_mesh(0.3f), red));
  box.items[0].pose = pose;
  mesh.items[0].pose = pose;
  const auto a = draw(*r, box, oblique_camera(w, h));
  const auto b = draw(*r, mesh, oblique_camera(w, h));
  int red_pixels = 0, differing = 0;
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col) {
      red_pixels += reddish(at(a, w, {col, row}));
      const Rgb p = at(a, w, {col, row}), q = at(b, w, {col, row});
      differing += std::abs(p.r - q.r) + std::abs(p.g - q.g) + std::abs(p.b - q.b) > 3;
    }
  CHECK(red_pixels > 300);
  CHECK(differing <= 4);  // at most a few edge pixels split differently
}

TEST_CASE("a mesh's own colours multiply the item colour, and faces turned away are not drawn", "[render][mesh]") {
  const int w = 48, h = 48;
  auto r = make_renderer("osmesa", w, h);
  auto coloured = cube_mesh(0.3f);
  coloured->colors.assign(coloured->positions.size(), Eigen::Vector3f(0.2f, 0.4f, 1.0f));
  Scene s;
  s.background = {0.0f, 0.0f, 0.0f};
  s.add(make_mesh(coloured, Eigen::Vector4f(1.0f, 0.5f, 1.0f, 1.0f)));
  const Camera cam = side_camera(w, h);  // looks at the +x face straight on
  const Rgb c = at(draw(*r, s, cam), w, {w / 2, h / 2});
  // Colour (0.2, 0.2, 1.0) times one shade: the channels keep those ratios.
  REQUIRE(c.b > 60);
  CHECK(std::abs(c.r - c.g) <= 1);
  CHECK(c.r == Approx(0.2 * c.b).margin(2));

  // The same cube turned inside out (every triangle wound the other way): only its far faces,
  // now facing the camera from inside, are drawn, and they are in shadow on this side.
  auto inside_out = cube_mesh(0.3f);
  for (std::size_t t = 0; t < inside_out->indices.size(); t += 3) std::swap(inside_out->indices[t + 1], inside_out->indices[t + 2]);
  Scene s2;
  s2.background = {0.0f, 0.0f, 0.0f};
  s2.add(make_mesh(inside_out, Eigen::Vector4f(1, 1, 1, 1)));
  const auto img = draw(*r, s2, cam);
  const Rgb back = at(img, w, {w / 2, h / 2});
  Scene s3 = s2;
  s3.items[0].mesh = cube_mesh(0.3f);
  const Rgb front = at(draw(*r, s3, cam), w, {w / 2, h / 2});
  CHECK(back.r != front.r);  // a different face is what shows
}
