#pragma once
#include <string>
#include <vector>

// `rdsim plot RUN... --out curves.png|svg`: the learning-curve figure of runs from their CSVs
// (rdsim/plot/), one colour per algorithm, mean and band over each algorithm's runs.
namespace rdsim {

struct PlotOptions {
  std::vector<std::string> runs;   // run folders, or folders holding run folders
  std::string out;                 // .png or .svg
  std::string metric = "success";  // success, return, length, kl, or any progress.csv column
  std::string x = "timesteps";     // or updates, episodes, wall_time
  std::string band = "std";        // std (mean ± 1 standard deviation) or minmax
  std::string title;               // default: "<env>: <metric>"
  double x_max = 0;                // > 0: draw only x <= x_max (every curve cut there)
  int window = 100;                // runs read from episodes.csv: the metric over this many last episodes
  int width = 800, height = 480;
};
int plot_command(const PlotOptions& options);

}  // namespace rdsim
