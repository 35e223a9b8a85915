// Manual benchmarks and the demo image; hidden from the default run (tags start with ".").
//   ./build/test_render "[.bench]"   frames per second of the ~20-item workspace scene, RGB alone and
//                                    with depth and segmentation read from the same pass
//   ./build/test_render "[.demo]"    writes /tmp/render_demo.png (RDSIM_RENDER_DEMO overrides)
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "rdsim/render/png.hpp"
#include "rdsim/render/renderer.hpp"
#include "render_test_util.hpp"

using namespace rdsim;

TEST_CASE("render frames per second, ~20-item workspace", "[.bench]") {
  Scene scene = test::workspace_scene();
  std::printf("scene items: %zu\n", scene.items.size());
  for (int side : {64, 84, 128, 224}) {
    auto r = make_renderer("osmesa", side, side);
    const Camera cam = make_orbit_camera(test::paper_main_view(), side, side);
    std::vector<std::uint8_t> img(static_cast<size_t>(side * side * 3));
    for (int i = 0; i < 20; ++i) r->render(scene, cam, img.data());  // warm-up: shader compiles
    const int frames = side <= 84 ? 4000 : 1000;
    const Eigen::Isometry3f target_pose = scene.items.back().pose;
    std::vector<float> depth(static_cast<size_t>(side * side));
    std::vector<std::uint8_t> segments(static_cast<size_t>(side * side));
    const RenderTargets rgb_only{.rgb = img.data()};
    const RenderTargets all{.rgb = img.data(), .depth = depth.data(), .segmentation = segments.data()};
    // Alternating halves of the frames, so both kinds see the same machine: rgb, all, rgb, all.
    double seconds[2] = {0.0, 0.0}, cpu[2] = {0.0, 0.0};
    for (int part = 0; part < 4; ++part) {
      const RenderTargets& targets = part % 2 ? all : rgb_only;
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();  // CPU time of all threads: less noisy when shared
      for (int i = 0; i < frames / 2; ++i) {
        // Pose updates as an env would do each step.
        Eigen::Isometry3f p = target_pose;
        p.translation().x() += 0.0001f * static_cast<float>(i % 100);
        scene.set_pose(static_cast<int>(scene.items.size()) - 1, p);
        r->render(scene, cam, targets);
      }
      seconds[part % 2] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu[part % 2] += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    }
    for (int kind = 0; kind < 2; ++kind)
      std::printf("%s %dx%d %s: %d frames in %.3f s = %.0f frames/s (%.3f ms/frame wall, %.3f ms CPU) [%s]\n",
                  r->backend().c_str(), side, side, kind ? "rgb+depth+segmentation" : "rgb", frames, seconds[kind],
                  frames / seconds[kind], 1e3 * seconds[kind] / frames, 1e3 * cpu[kind] / frames, r->device().c_str());
    std::printf("  rgb+depth+segmentation / rgb frame rate: %.2f\n", seconds[0] / seconds[1]);
    CHECK(img[0] != 0);
  }
}

TEST_CASE("demo image of the paper's two views", "[.demo]") {
  const char* env = std::getenv("RDSIM_RENDER_DEMO");
  const std::string path = env ? env : "/tmp/render_demo.png";
  const int w = 320, h = 240;
  const Scene scene = test::workspace_scene();
  auto r = make_renderer("osmesa", w, h);
  // Main view on the left, second view on the right, one PNG.
  std::vector<std::uint8_t> left(static_cast<size_t>(w * h * 3)), right(left.size());
  r->render(scene, make_orbit_camera(test::paper_main_view(), w, h), left.data());
  r->render(scene, make_orbit_camera(test::paper_second_view(), w, h), right.data());
  std::vector<std::uint8_t> both(left.size() * 2);
  const size_t row = static_cast<size_t>(w) * 3;
  for (int y = 0; y < h; ++y) {
    std::copy_n(left.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y)), row,
                both.begin() + static_cast<std::ptrdiff_t>(2 * row * static_cast<size_t>(y)));
    std::copy_n(right.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y)), row,
                both.begin() + static_cast<std::ptrdiff_t>(2 * row * static_cast<size_t>(y) + row));
  }
  write_png(path, 2 * w, h, 3, both.data());
  std::printf("wrote %s (%dx%d)\n", path.c_str(), 2 * w, h);
  CHECK(left != right);
}
