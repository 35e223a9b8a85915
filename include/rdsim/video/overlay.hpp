#pragma once
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"

// A small caption drawn into a frame's top-left corner: light text on a dark translucent box,
// one line per string, rendered with cairo (fonts from fontconfig, e.g. DejaVu Sans).
namespace rdsim {

struct OverlayLine {
  std::string text;
  bool highlight = false;  // drawn in green (e.g. "success")
};

// Draws onto `frame` in place; the text size follows the frame's height.
void draw_overlay(Image& frame, const std::vector<OverlayLine>& lines);

}  // namespace rdsim
