// The optional egl backend. Always compiled; the cases that need it return early with a warning
// when this build has no egl backend or the machine no usable EGL device.
//   ./build/test_render "egl vs osmesa*"   frames per second, egl vs osmesa (hidden benchmark)
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rdsim/core/env_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/render/renderer.hpp"
#include "render_test_util.hpp"

using Catch::Matchers::Contains;
using namespace rdsim;
using namespace rdsim::test;

namespace {

bool egl_built() {
  const auto names = renderer_backends();
  return std::find(names.begin(), names.end(), "egl") != names.end();
}

// Why egl cannot be used here, or "" when it can (probed once per process).
const std::string& egl_unavailable_reason() {
  static const std::string reason = []() -> std::string {
    if (!egl_built()) return "this build has no egl backend (EGL not found by CMake)";
    try {
      make_renderer("egl", 8, 8);
      return "";
    } catch (const Error& e) {
      return e.what();
    }
  }();
  return reason;
}

bool egl_available() {
  if (egl_unavailable_reason().empty()) return true;
  WARN("egl case skipped: " << egl_unavailable_reason());
  return false;
}

std::vector<std::uint8_t> draw(Renderer& r, const Scene& s, const Camera& c) {
  std::vector<std::uint8_t> img(static_cast<size_t>(r.width()) * static_cast<size_t>(r.height()) * 3);
  r.render(s, c, img.data());
  return img;
}

struct Diff {
  int max_abs = 0;
  size_t bytes = 0;  // bytes that differ at all
};

Diff compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  REQUIRE(a.size() == b.size());
  Diff d;
  for (size_t i = 0; i < a.size(); ++i) {
    const int delta = std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
    d.max_abs = std::max(d.max_abs, delta);
    d.bytes += delta != 0;
  }
  return d;
}

// Distinct colours in an image: a blank or single-colour frame would make comparisons vacuous.
size_t colour_count(const std::vector<std::uint8_t>& img) {
  std::vector<std::uint32_t> colours;
  for (size_t i = 0; i + 2 < img.size(); i += 3)
    colours.push_back(static_cast<std::uint32_t>(img[i]) << 16 | static_cast<std::uint32_t>(img[i + 1]) << 8 | img[i + 2]);
  std::sort(colours.begin(), colours.end());
  return static_cast<size_t>(std::unique(colours.begin(), colours.end()) - colours.begin());
}

// Compared through a bool so a failure does not print whole images.
bool same(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) { return a == b; }

bool is_llvmpipe(const Renderer& r) { return r.device().find("llvmpipe") != std::string::npos; }

}  // namespace

TEST_CASE("egl draws the workspace scene like osmesa", "[render][egl]") {
  if (!egl_available()) return;
  // Odd sizes too: rows not 4-byte aligned, width != height.
  for (auto [w, h] : {std::pair{64, 64}, std::pair{224, 224}, std::pair{97, 61}}) {
    auto egl = make_renderer("egl", w, h);
    auto osmesa = make_renderer("osmesa", w, h);
    CHECK(egl->backend() == "egl");
    CHECK(egl->width() == w);
    CHECK(egl->height() == h);
    CHECK_FALSE(egl->device().empty());
    const Scene s = workspace_scene();
    for (const OrbitView& view : {paper_main_view(), paper_second_view()}) {
      const Camera cam = make_orbit_camera(view, w, h);
      const auto a = draw(*egl, s, cam);
      const auto b = draw(*osmesa, s, cam);
      CHECK(colour_count(a) > 20);
      const Diff d = compare(a, b);
      INFO(w << "x" << h << " egl on " << egl->device() << " vs osmesa on " << osmesa->device()
              << ": max abs difference " << d.max_abs << ", " << d.bytes << " of " << a.size()
              << " bytes differ");
      // Same llvmpipe rasteriser, buffer formats (RGBA8 colour, 24-bit depth) and GL calls: the
      // images agree byte for byte here (measured: 0 bytes differ at all three sizes). Mesa probably
      // stores FBOs upside down relative to window buffers, so a pixel exactly on an edge shared
      // by two triangles may take the other one's colour: in env runs about one pixel in 50 frames
      // differs (by 1 level, 3 bytes in 614,400). Allow 0.1% of the bytes for that, no more. A GPU
      // rasterises and rounds its own way, so there only the picture as a whole must agree.
      if (is_llvmpipe(*egl) && is_llvmpipe(*osmesa))
        CHECK(d.bytes <= a.size() / 1000);
      else
        CHECK(d.bytes < a.size() / 50);
    }
  }
}

TEST_CASE("egl gives osmesa's depth and segmentation images", "[render][egl][depth][segmentation]") {
  if (!egl_available()) return;
  const int w = 64, h = 48;
  auto egl = make_renderer("egl", w, h);
  auto osmesa = make_renderer("osmesa", w, h);
  Scene s = workspace_scene();
  for (std::size_t i = 0; i < s.items.size(); ++i) s.items[i].segment = static_cast<std::uint8_t>(1 + i);
  const Camera cam = make_orbit_camera(paper_main_view(), w, h);
  const auto n = static_cast<std::size_t>(w * h);
  std::vector<float> depth_egl(n), depth_osmesa(n);
  std::vector<std::uint8_t> seg_egl(n), seg_osmesa(n);
  egl->render(s, cam, RenderTargets{.depth = depth_egl.data(), .segmentation = seg_egl.data()});
  osmesa->render(s, cam, RenderTargets{.depth = depth_osmesa.data(), .segmentation = seg_osmesa.data()});
  std::size_t ids_differ = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    ids_differ += seg_egl[i] != seg_osmesa[i];
    if (seg_egl[i] == seg_osmesa[i]) worst = std::max(worst, static_cast<double>(std::abs(depth_egl[i] - depth_osmesa[i])));
  }
  INFO("egl on " << egl->device() << ": " << ids_differ << " ids of " << n << " differ; largest depth difference "
                 << worst << " m");
  // As for colour (above): on llvmpipe a pixel on a shared edge may fall to the other triangle.
  CHECK(ids_differ <= (is_llvmpipe(*egl) && is_llvmpipe(*osmesa) ? n / 1000 : n / 50));
  CHECK(worst <= 1e-3);
}

TEST_CASE("egl rendering is deterministic, across frames and across renderers", "[render][egl]") {
  if (!egl_available()) return;
  Scene s = workspace_scene();
  const Camera cam = make_orbit_camera(paper_main_view(), 64, 64);
  auto a = make_renderer("egl", 64, 64);
  const auto first = draw(*a, s, cam);
  CHECK(same(draw(*a, s, cam), first));
  auto b = make_renderer("egl", 64, 64);
  CHECK(same(draw(*b, s, cam), first));
  // A moved item changes the frame, and moving it back restores it exactly.
  const int last = static_cast<int>(s.items.size()) - 1;
  const Eigen::Isometry3f pose = s.items.back().pose;
  s.set_pose(last, at_position(pose.translation() + Eigen::Vector3f(0.0f, 0.15f, 0.0f)));
  CHECK_FALSE(same(draw(*a, s, cam), first));
  s.set_pose(last, pose);
  CHECK(same(draw(*a, s, cam), first));
}

TEST_CASE("egl renderers of different sizes, and osmesa ones, work side by side", "[render][egl]") {
  if (!egl_available()) return;
  const Scene s = workspace_scene();
  const Camera small_cam = make_orbit_camera(paper_main_view(), 32, 24);
  const Camera big_cam = make_orbit_camera(paper_second_view(), 96, 80);
  auto small = make_renderer("egl", 32, 24);
  const auto small_alone = draw(*small, s, small_cam);
  auto big = make_renderer("egl", 96, 80);
  const auto big_alone = draw(*big, s, big_cam);
  // A third size and view: a frame drawn in the wrong context would come out wrong.
  const Camera os_cam = make_orbit_camera(paper_main_view(), 80, 60);
  auto os = make_renderer("osmesa", 80, 60);
  const auto os_alone = draw(*os, s, os_cam);
  CHECK(colour_count(small_alone) > 10);
  CHECK(colour_count(big_alone) > 10);
  // Interleaving must not leak one renderer's size, framebuffer or context into another.
  for (int round = 0; round < 3; ++round) {
    CHECK(same(draw(*small, s, small_cam), small_alone));
    CHECK(same(draw(*os, s, os_cam), os_alone));
    CHECK(same(draw(*big, s, big_cam), big_alone));
  }
  // The same egl renderer right after an osmesa one: both Mesa backends share one GL dispatch.
  for (int round = 0; round < 3; ++round) {
    CHECK(same(draw(*big, s, big_cam), big_alone));
    CHECK(same(draw(*os, s, os_cam), os_alone));
  }
  CHECK_THROWS_WITH(small->render(s, big_cam, nullptr), Contains("96x80"));
  // A renderer destroyed in between leaves the others working.
  small.reset();
  CHECK(same(draw(*big, s, big_cam), big_alone));
  CHECK(same(draw(*os, s, os_cam), os_alone));
  // And so does an osmesa renderer destroyed while it was the one bound.
  os.reset();
  CHECK(same(draw(*big, s, big_cam), big_alone));
}

TEST_CASE("renderer names: unknown ones list the built backends, auto picks one that works",
          "[render][egl]") {
  const auto names = renderer_backends();
  CHECK(std::find(names.begin(), names.end(), "osmesa") != names.end());
  CHECK(std::find(names.begin(), names.end(), "auto") == names.end());
  try {
    make_renderer("opengl", 8, 8);
    FAIL("an unknown backend was accepted");
  } catch (const Error& e) {
    const std::string msg = e.what();
    CHECK_THAT(msg, Contains("\"opengl\"") && Contains("auto"));
    for (const std::string& n : names) CHECK_THAT(msg, Contains(n));
    if (!egl_built()) CHECK_THAT(msg, !Contains("egl"));
  }
  auto chosen = make_renderer("auto", 16, 12);
  CHECK(chosen->width() == 16);
  CHECK(chosen->height() == 12);
  CHECK(chosen->backend() == (egl_unavailable_reason().empty() ? "egl" : "osmesa"));
  CHECK_THROWS_AS(make_renderer("auto", 0, 8), Error);
}

TEST_CASE("egl vs osmesa frames per second, ~20-item workspace", "[.bench]") {
  if (!egl_available()) return;
  Scene scene = workspace_scene();
  const int frames_for[] = {4000, 1000};
  int size_index = 0;
  for (int side : {64, 224}) {
    for (const char* backend : {"osmesa", "egl"}) {
      auto r = make_renderer(backend, side, side);
      const Camera cam = make_orbit_camera(paper_main_view(), side, side);
      std::vector<std::uint8_t> img(static_cast<size_t>(side * side * 3));
      for (int i = 0; i < 20; ++i) r->render(scene, cam, img.data());  // warm-up: shader compiles
      const int frames = frames_for[size_index];
      const Eigen::Isometry3f target_pose = scene.items.back().pose;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < frames; ++i) {
        Eigen::Isometry3f p = target_pose;  // a pose update per frame, as an env step does
        p.translation().x() += 0.0001f * static_cast<float>(i % 100);
        scene.set_pose(static_cast<int>(scene.items.size()) - 1, p);
        r->render(scene, cam, img.data());
      }
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%-6s %3dx%-3d: %d frames in %.3f s = %6.0f frames/s (%.3f ms/frame) [%s]\n", backend,
                  side, side, frames, s, frames / s, 1e3 * s / frames, r->device().c_str());
      scene.set_pose(static_cast<int>(scene.items.size()) - 1, target_pose);
    }
    ++size_index;
  }
}
