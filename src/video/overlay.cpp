#include "rdsim/video/overlay.hpp"

#include <cairo.h>

#include <algorithm>
#include <cstdint>

namespace rdsim {

void draw_overlay(Image& frame, const std::vector<OverlayLine>& lines) {
  if (lines.empty() || frame.width <= 0 || frame.height <= 0) return;
  const int w = frame.width, h = frame.height;
  // cairo draws on 32-bit xRGB pixels: copy in, draw, copy back.
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  const int stride = cairo_image_surface_get_stride(surface);
  unsigned char* data = cairo_image_surface_get_data(surface);
  cairo_surface_flush(surface);
  for (int y = 0; y < h; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    const std::uint8_t* rgb = frame.rgb.data() + static_cast<std::size_t>(y) * w * 3;
    for (int x = 0; x < w; ++x) row[x] = (0xffu << 24) | (rgb[3 * x] << 16) | (rgb[3 * x + 1] << 8) | rgb[3 * x + 2];
  }
  cairo_surface_mark_dirty(surface);

  cairo_t* cr = cairo_create(surface);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
  const double size = std::clamp(h / 20.0, 9.0, 28.0);
  cairo_set_font_size(cr, size);
  cairo_font_extents_t font;
  cairo_font_extents(cr, &font);
  double text_width = 0;
  for (const auto& line : lines) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, line.text.c_str(), &e);
    text_width = std::max(text_width, e.x_advance);
  }
  const double pad = size * 0.4, line_height = font.height;
  cairo_set_source_rgba(cr, 0, 0, 0, 0.55);
  cairo_rectangle(cr, 0, 0, text_width + 2 * pad, line_height * static_cast<double>(lines.size()) + 2 * pad);
  cairo_fill(cr);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].highlight) {
      cairo_set_source_rgb(cr, 0.45, 0.95, 0.45);
    } else {
      cairo_set_source_rgb(cr, 1, 1, 1);
    }
    cairo_move_to(cr, pad, pad + font.ascent + line_height * static_cast<double>(i));
    cairo_show_text(cr, lines[i].text.c_str());
  }
  cairo_destroy(cr);
  cairo_surface_flush(surface);

  for (int y = 0; y < h; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    std::uint8_t* rgb = frame.rgb.data() + static_cast<std::size_t>(y) * w * 3;
    for (int x = 0; x < w; ++x) {
      rgb[3 * x] = static_cast<std::uint8_t>(row[x] >> 16);
      rgb[3 * x + 1] = static_cast<std::uint8_t>(row[x] >> 8);
      rgb[3 * x + 2] = static_cast<std::uint8_t>(row[x]);
    }
  }
  cairo_surface_destroy(surface);
}

}  // namespace rdsim
