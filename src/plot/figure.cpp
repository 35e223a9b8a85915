#include "rdsim/plot/figure.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

#include "axis_ticks.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace rdsim {
namespace {

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using Context = std::unique_ptr<cairo_t, ContextDeleter>;

cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Text with its anchor at (x, y): ax, ay in 0..1 pick the point of the text's box (0.5, 0.5: centre).
void text_at(cairo_t* cr, const std::string& text, double x, double y, double ax, double ay, double angle = 0) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, angle);
  cairo_move_to(cr, -e.x_bearing - ax * e.width, -e.y_bearing - ay * e.height);
  cairo_show_text(cr, text.c_str());
  cairo_restore(cr);
}

std::string legend_entry(const CurveBand& b) {
  return (b.algorithm.empty() ? std::string("(unknown)") : upper(b.algorithm)) + " (" + std::to_string(b.runs) +
         (b.runs == 1 ? " run)" : " runs)");
}

void draw(cairo_t* cr, const std::vector<CurveBand>& bands, const FigureText& text, int width, int height) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

  // The legend sits right of the plot, so it never hides a curve.
  cairo_set_font_size(cr, 13);
  double legend_width = 0;
  for (const auto& b : bands) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, legend_entry(b).c_str(), &e);
    legend_width = std::max(legend_width, e.x_advance + 24);
  }
  cairo_set_font_size(cr, 11);
  cairo_text_extents_t band_extents;
  cairo_text_extents(cr, text.band_label.c_str(), &band_extents);
  legend_width = std::max(legend_width, band_extents.x_advance);
  const double left = 78, top = 46, bottom = height - 56.0;
  const double right = width - (legend_width + 30);

  double x_low = INFINITY, x_high = -INFINITY, y_low = INFINITY, y_high = -INFINITY;
  for (const auto& b : bands) {
    x_low = std::min(x_low, b.x.front());
    x_high = std::max(x_high, b.x.back());
    y_low = std::min(y_low, *std::min_element(b.low.begin(), b.low.end()));
    y_high = std::max(y_high, *std::max_element(b.high.begin(), b.high.end()));
  }
  // x from 0 (or its first value) to its last value; y over the data with a margin.
  const Ticks xt = nice_ticks(std::min(x_low, 0.0), x_high);
  const double y_pad = (y_high > y_low ? y_high - y_low : std::max(std::abs(y_high), 1.0)) * 0.04;
  const Ticks yt = nice_ticks(y_low - y_pad, y_high + y_pad);
  auto px = [&](double x) { return left + (x - xt.low) / (xt.high - xt.low) * (right - left); };
  auto py = [&](double y) { return bottom - (y - yt.low) / (yt.high - yt.low) * (bottom - top); };

  // Grid, ticks and their labels.
  cairo_set_line_width(cr, 1);
  cairo_set_font_size(cr, 12);
  for (double v : xt.values) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, std::round(px(v)) + 0.5, top);
    cairo_line_to(cr, std::round(px(v)) + 0.5, bottom);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text_at(cr, tick_label(v, xt.step), px(v), bottom + 7, 0.5, 0);
  }
  for (double v : yt.values) {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, left, std::round(py(v)) + 0.5);
    cairo_line_to(cr, right, std::round(py(v)) + 0.5);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text_at(cr, tick_label(v, yt.step), left - 7, py(v), 1, 0.5);
  }
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  cairo_rectangle(cr, left + 0.5, top + 0.5, right - left, bottom - top);
  cairo_stroke(cr);

  // Bands, then the mean lines on top, clipped to the plot.
  cairo_save(cr);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_clip(cr);
  for (std::size_t k = 0; k < bands.size(); ++k) {
    const CurveBand& b = bands[k];
    const Rgb c = algorithm_colour(b.algorithm, k);
    cairo_new_path(cr);
    for (std::size_t i = 0; i < b.x.size(); ++i) cairo_line_to(cr, px(b.x[i]), py(b.high[i]));
    for (std::size_t i = b.x.size(); i-- > 0;) cairo_line_to(cr, px(b.x[i]), py(b.low[i]));
    cairo_close_path(cr);
    cairo_set_source_rgba(cr, c.r, c.g, c.b, 0.22);
    cairo_fill(cr);
  }
  cairo_set_line_width(cr, 2);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (std::size_t k = 0; k < bands.size(); ++k) {
    const CurveBand& b = bands[k];
    const Rgb c = algorithm_colour(b.algorithm, k);
    cairo_new_path(cr);
    for (std::size_t i = 0; i < b.x.size(); ++i) cairo_line_to(cr, px(b.x[i]), py(b.mean[i]));
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_stroke(cr);
  }
  cairo_restore(cr);

  // Title, axis labels, legend.
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_font_size(cr, 16);
  text_at(cr, text.title, (left + right) / 2, 14, 0.5, 0);
  cairo_set_font_size(cr, 13);
  text_at(cr, text.x_label, (left + right) / 2, height - 8.0, 0.5, 1);
  text_at(cr, text.y_label, 14, (top + bottom) / 2, 0.5, 0, -M_PI / 2);
  double y = top + 4;
  for (std::size_t k = 0; k < bands.size(); ++k) {
    const Rgb c = algorithm_colour(bands[k].algorithm, k);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, right + 14, y + 2, 18, 10);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text_at(cr, legend_entry(bands[k]), right + 38, y + 7, 0, 0.5);
    y += 22;
  }
  if (!text.band_label.empty()) {
    cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
    cairo_set_font_size(cr, 11);
    text_at(cr, text.band_label, right + 14, y + 4, 0, 0);
  }
}

}  // namespace

Rgb algorithm_colour(const std::string& algorithm, std::size_t place) {
  // One colour per algorithm rdsim has, so a figure of all ten tells them apart: the Okabe-Ito
  // colour-blind-safe set (blue, vermillion, bluish green, orange, reddish purple, sky blue, yellow,
  // black), then grey and brown. Other names take the set's colours by their place.
  static const std::pair<const char*, Rgb> fixed[] = {
      {"ppo", {0.00, 0.45, 0.70}},    {"a2c", {0.84, 0.37, 0.00}},  {"dqn", {0.00, 0.62, 0.45}},
      {"trpo", {0.90, 0.62, 0.00}},   {"sac", {0.80, 0.47, 0.65}},  {"td3", {0.34, 0.71, 0.91}},
      {"ddpg", {0.85, 0.80, 0.10}},   {"ars", {0.00, 0.00, 0.00}},  {"cma_es", {0.55, 0.55, 0.55}},
      {"random", {0.55, 0.34, 0.16}}, {"bc", {0.40, 0.20, 0.55}}};
  for (const auto& [name, colour] : fixed)
    if (algorithm == name) return colour;
  return fixed[place % (sizeof fixed / sizeof fixed[0])].second;
}

namespace {

// A white page, then each panel in its band of the page.
void draw_panels(cairo_t* cr, const std::vector<FigurePanel>& panels, int width, int panel_height) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  for (std::size_t i = 0; i < panels.size(); ++i) {
    cairo_save(cr);
    cairo_translate(cr, 0, static_cast<double>(i) * panel_height);
    draw(cr, panels[i].bands, panels[i].text, width, panel_height);
    cairo_restore(cr);
  }
}

}  // namespace

void write_figure(const std::vector<CurveBand>& bands, const FigureText& text, const std::string& path, int width,
                  int height) {
  write_figure(std::vector<FigurePanel>{{bands, text}}, path, width, height);
}

void write_figure(const std::vector<FigurePanel>& panels, const std::string& path, int width, int panel_height) {
  for (const auto& p : panels)
    if (p.bands.empty()) throw Error(path + ": no curves to draw");
  if (panels.empty()) throw Error(path + ": no curves to draw");
  const int height = panel_height * static_cast<int>(panels.size());
  const std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  std::string bytes;
  if (ext == ".png") {
    Surface surface(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height));
    Context cr(cairo_create(surface.get()));
    draw_panels(cr.get(), panels, width, panel_height);
    cairo_surface_flush(surface.get());
    if (cairo_surface_write_to_png_stream(surface.get(), append_bytes, &bytes) != CAIRO_STATUS_SUCCESS) {
      throw Error(path + ": cannot encode the PNG");
    }
  } else if (ext == ".svg") {
    Surface surface(cairo_svg_surface_create_for_stream(append_bytes, &bytes, width, height));
    {
      Context cr(cairo_create(surface.get()));
      draw_panels(cr.get(), panels, width, panel_height);
    }
    cairo_surface_finish(surface.get());
    if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) throw Error(path + ": cannot encode the SVG");
  } else {
    throw Error(path + ": expected a file name ending in .png or .svg");
  }
  write_file_atomic(path, bytes);
}

}  // namespace rdsim
