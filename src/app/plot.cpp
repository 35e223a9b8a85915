// `rdsim plot`: learning-curve figures from run folders.
#include "rdsim/app/plot.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/run_files.hpp"
#include "rdsim/plot/figure.hpp"
#include "rdsim/plot/learning_curves.hpp"

namespace rdsim {
namespace {

struct Metric {
  std::string column, label;
};

// Short names for the common metrics; any other name is a progress.csv column.
Metric metric_named(const std::string& name) {
  if (name == "success") return {"success_rate", "success rate"};
  if (name == "return") return {"mean_return", "mean return"};
  if (name == "length") return {"mean_length", "episode length"};
  if (name == "kl") return {"approx_kl", "approximate KL"};
  std::string label = name;
  for (char& c : label) c = c == '_' ? ' ' : c;
  return {name, label};
}

std::string x_label(const std::string& x) { return x == "wall_time" ? "wall time (s)" : metric_named(x).label; }

}  // namespace

int plot_command(const PlotOptions& o) {
  if (o.band != "std" && o.band != "minmax") throw Error("plot: --band: expected std or minmax");
  std::vector<std::string> dirs;
  for (const auto& path : o.runs) {
    const auto found = find_run_folders(path);
    if (found.empty()) throw Error(path + ": no run folder (a folder holding progress.csv) at or below it");
    dirs.insert(dirs.end(), found.begin(), found.end());
  }
  const Metric metric = metric_named(o.metric);
  std::vector<RunCurve> curves;
  std::set<std::string> envs;
  for (const auto& dir : dirs) {
    curves.push_back(read_run_curve(dir, o.x, metric.column));
    if (o.x_max > 0) curves.back() = crop_run_curve(curves.back(), o.x_max);
    if (!curves.back().info.env.empty()) envs.insert(curves.back().info.env);
  }
  const auto bands = mean_over_runs(curves, o.band == "std" ? Band::StdDev : Band::MinMax);

  FigureText text;
  std::string env_names;
  for (const auto& e : envs) env_names += (env_names.empty() ? "" : ", ") + e;
  text.title = !o.title.empty() ? o.title : (env_names.empty() ? "" : env_names + ": ") + metric.label;
  text.x_label = x_label(o.x);
  text.y_label = metric.label;
  const bool several = std::any_of(bands.begin(), bands.end(), [](const CurveBand& b) { return b.runs > 1; });
  if (several) text.band_label = o.band == "std" ? "mean ± 1 std over runs" : "mean, min to max over runs";
  write_figure(bands, text, o.out, o.width, o.height);

  std::printf("rdsim plot: %s from %zu run%s\n", o.out.c_str(), dirs.size(), dirs.size() == 1 ? "" : "s");
  for (const auto& b : bands) {
    std::printf("  %s (%d run%s): %s at %s %.0f: %.3f (band %.3f to %.3f)\n",
                b.algorithm.empty() ? "(unknown)" : b.algorithm.c_str(), b.runs, b.runs == 1 ? "" : "s",
                metric.label.c_str(), o.x.c_str(), b.x.back(), b.mean.back(), b.low.back(), b.high.back());
  }
  return 0;
}

Command plot_command_entry() {
  return {"plot", "Draw the learning curves of runs (mean and band over each algorithm's runs) from their "
          "progress.csv, as PNG or SVG",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<PlotOptions>();
            cmd.add_option("runs", o->runs, "Run folders, or folders holding run folders")->required();
            cmd.add_option("-o,--out", o->out, "Figure to write: FILE.png or FILE.svg")->required();
            cmd.add_option("--metric", o->metric, "success, return, length, kl, or any progress.csv column")->capture_default_str();
            cmd.add_option("--x", o->x, "x axis: a progress.csv column (timesteps, updates, episodes, wall_time)")->capture_default_str();
            cmd.add_option("--band", o->band, "std: mean ± 1 standard deviation over runs; minmax: their range")
                ->check(CLI::IsMember({"std", "minmax"}))
                ->capture_default_str();
            cmd.add_option("--title", o->title, "Title (default: env and metric)");
            cmd.add_option("--x-max", o->x_max,
                           "Draw x up to this value only (e.g. 1e6 timesteps), cutting longer runs there; default: all")
                ->check(CLI::PositiveNumber);
            cmd.add_option("--width", o->width, "Width in pixels")->check(CLI::Range(200, 8000))->capture_default_str();
            cmd.add_option("--height", o->height, "Height in pixels")->check(CLI::Range(150, 8000))->capture_default_str();
            return [o] { return plot_command(*o); };
          }};
}

}  // namespace rdsim
