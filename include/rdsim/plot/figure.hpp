#pragma once
#include <string>
#include <vector>

#include "rdsim/plot/learning_curves.hpp"

// The learning-curve figure (RobotDrlSim's Figures 3-5): per algorithm a mean line and a shaded
// band, one colour per algorithm, a title, axis labels and a legend. Drawn with cairo, so the same
// drawing gives a PNG or an SVG.
namespace rdsim {

struct FigureText {
  std::string title;        // "jaka_button: success rate"
  std::string x_label;      // "timesteps"
  std::string y_label;      // "success rate"
  std::string band_label;   // what the band is, shown under the legend ("band: ± 1 std over seeds")
};

// Writes the figure to `path`, PNG or SVG by its extension (.png, .svg), width x height pixels
// (points for SVG), atomically. Throws rdsim::Error for another extension or when it cannot write.
void write_figure(const std::vector<CurveBand>& bands, const FigureText& text, const std::string& path,
                  int width = 800, int height = 480);

// One plot of a figure with several (one per env): its curves and texts.
struct FigurePanel {
  std::vector<CurveBand> bands;
  FigureText text;
};

// The panels one below the other, each width x panel_height, in one file (as write_figure above).
void write_figure(const std::vector<FigurePanel>& panels, const std::string& path, int width = 800,
                  int panel_height = 480);

// The colour of an algorithm in every figure (fixed for each of rdsim's algorithms; other names by their place).
struct Rgb {
  double r, g, b;
};
Rgb algorithm_colour(const std::string& algorithm, std::size_t place);

}  // namespace rdsim
