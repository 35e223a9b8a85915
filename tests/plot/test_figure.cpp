#include <catch2/catch.hpp>
#include <cairo.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "rdsim/core/error.hpp"
#include "rdsim/plot/figure.hpp"
#include "../scratch_dir.hpp"

namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) {
  static const rdsim::test::ScratchDir root("figure");  // removed when the test program exits
  return root / name;
}

std::vector<rdsim::CurveBand> two_algorithms() {
  std::vector<rdsim::CurveBand> bands(2);
  bands[0].algorithm = "a2c";
  bands[1].algorithm = "ppo";
  for (auto& b : bands) {
    b.runs = 3;
    const double speed = b.algorithm == "ppo" ? 2.0 : 1.0;
    for (int i = 0; i <= 100; ++i) {
      const double x = i * 3000.0, y = 1 - std::exp(-speed * i / 30.0);
      b.x.push_back(x);
      b.mean.push_back(y);
      b.low.push_back(y - 0.1);
      b.high.push_back(y + 0.1);
    }
  }
  return bands;
}

// Pixels of the PNG close to a colour (0..1 channels).
int count_near(cairo_surface_t* png, rdsim::Rgb c) {
  const int w = cairo_image_surface_get_width(png), h = cairo_image_surface_get_height(png);
  const int stride = cairo_image_surface_get_stride(png);
  const unsigned char* data = cairo_image_surface_get_data(png);
  int n = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = data + y * stride + x * 4;  // B, G, R, A in memory on little endian
      if (std::abs(p[2] - c.r * 255) < 12 && std::abs(p[1] - c.g * 255) < 12 && std::abs(p[0] - c.b * 255) < 12) ++n;
    }
  }
  return n;
}

}  // namespace

TEST_CASE("figure: a PNG with each algorithm's line and band in its colour", "[plot]") {
  const std::string path = scratch("curves.png");
  rdsim::write_figure(two_algorithms(), {"jaka_button: success rate", "timesteps", "success rate", "mean ± 1 std"},
                      path, 640, 400);
  cairo_surface_t* png = cairo_image_surface_create_from_png(path.c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  CHECK(cairo_image_surface_get_width(png) == 640);
  CHECK(cairo_image_surface_get_height(png) == 400);
  CHECK(count_near(png, rdsim::algorithm_colour("ppo", 0)) > 300);  // the line and the legend swatch
  CHECK(count_near(png, rdsim::algorithm_colour("a2c", 0)) > 300);
  CHECK(count_near(png, {0.0, 0.62, 0.45}) < 5);  // no DQN here
  cairo_surface_destroy(png);
}

TEST_CASE("figure: an SVG of the same drawing, other extensions are refused", "[plot]") {
  const std::string path = scratch("curves.svg");
  rdsim::write_figure(two_algorithms(), {"title", "timesteps", "success rate", ""}, path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  CHECK(text.str().find("<svg") != std::string::npos);
  CHECK(text.str().find("<path") != std::string::npos);
  CHECK_THROWS_WITH(rdsim::write_figure(two_algorithms(), {}, scratch("curves.jpg")), Catch::Contains(".png or .svg"));
  CHECK_THROWS_WITH(rdsim::write_figure({}, {}, scratch("none.png")), Catch::Contains("no curves"));
  CHECK_THROWS_AS(rdsim::write_figure(two_algorithms(), {}, "/proc/nonexistent-folder/x.png"), rdsim::Error);
}

TEST_CASE("figure: one panel per env, one below the other", "[plot]") {
  const std::string path = scratch("panels.png");
  rdsim::FigureText a, b;
  a.title = "cartpole: success rate";
  b.title = "jaka_button: success rate";
  rdsim::write_figure(std::vector<rdsim::FigurePanel>{{two_algorithms(), a}, {two_algorithms(), b}}, path, 640, 300);
  cairo_surface_t* png = cairo_image_surface_create_from_png(path.c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  CHECK(cairo_image_surface_get_width(png) == 640);
  CHECK(cairo_image_surface_get_height(png) == 600);
  // Both panels hold the curves: PPO's colour in the top half and in the bottom half.
  cairo_surface_t* top = cairo_surface_create_for_rectangle(png, 0, 0, 640, 300);
  cairo_surface_t* bottom = cairo_surface_create_for_rectangle(png, 0, 300, 640, 300);
  cairo_surface_t* top_image = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 640, 300);
  cairo_surface_t* bottom_image = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 640, 300);
  for (auto [from, to] : {std::pair{top, top_image}, std::pair{bottom, bottom_image}}) {
    cairo_t* cr = cairo_create(to);
    cairo_set_source_surface(cr, from, 0, 0);
    cairo_paint(cr);
    cairo_destroy(cr);
    cairo_surface_flush(to);
    CHECK(count_near(to, rdsim::algorithm_colour("ppo", 0)) > 300);
  }
  for (auto* s : {top, bottom, top_image, bottom_image, png}) cairo_surface_destroy(s);
}
