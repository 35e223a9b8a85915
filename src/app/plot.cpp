// `rdsim plot`: learning-curve figures from run folders.
#include "rdsim/app/plot.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
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
  std::string episodes_column;  // the per-episode column it is the mean of in episodes.csv; "" when none
};

// Short names for the common metrics; any other name is a progress.csv column.
Metric metric_named(const std::string& name) {
  if (name == "success") return {"success_rate", "success rate", "success"};
  if (name == "return") return {"mean_return", "mean return", "return"};
  if (name == "length") return {"mean_length", "episode length", "length"};
  if (name == "kl") return {"approx_kl", "approximate KL", ""};
  std::string label = name;
  for (char& c : label) c = c == '_' ? ' ' : c;
  return {name, label, ""};
}

// A run's curve from its progress.csv, or where it has none (a run of another program, e.g.
// examples/sb3_her.py --log-dir) from its episodes.csv: the metric over the last `window` episodes.
RunCurve read_curve(const std::string& dir, const PlotOptions& o, const Metric& metric) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(fs::path(dir) / progress_csv_name, ec) || !fs::exists(fs::path(dir) / episodes_csv_name, ec))
    return read_run_curve(dir, o.x, metric.column);
  if (metric.episodes_column.empty()) {
    throw Error(dir + ": no progress.csv, and its episodes.csv gives --metric success, return or length only, not \"" +
                o.metric + "\"");
  }
  if (o.x == "updates")
    throw Error(dir + ": no progress.csv, and its episodes.csv has no --x updates (timesteps, episodes or wall_time)");
  return read_episode_curve(dir, o.x == "episodes" ? "episode" : o.x, metric.episodes_column, o.window);
}

std::string x_label(const std::string& x) { return x == "wall_time" ? "wall time (s)" : metric_named(x).label; }

// An x value as the summary prints it: whole numbers (timesteps, updates) in full, others (wall
// time in seconds) to 4 significant digits, so a short run never reads "at wall_time 0".
std::string x_value(double x) {
  char text[40];
  std::snprintf(text, sizeof text, x == std::floor(x) && std::abs(x) < 1e15 ? "%.0f" : "%.4g", x);
  return text;
}

}  // namespace

int plot_command(const PlotOptions& o) {
  if (o.band != "std" && o.band != "minmax") throw Error("plot: --band: expected std or minmax");
  std::vector<std::string> dirs;
  for (const auto& path : o.runs) {
    const auto found = find_run_folders(path);
    if (found.empty()) throw Error(path + ": no run folder (a folder holding progress.csv or config.json) at or below it");
    dirs.insert(dirs.end(), found.begin(), found.end());
  }
  const Metric metric = metric_named(o.metric);
  std::vector<RunCurve> curves;
  for (const auto& dir : dirs) {
    curves.push_back(read_curve(dir, o, metric));
    if (o.x_max > 0) curves.back() = crop_run_curve(curves.back(), o.x_max);
  }

  // One panel per env: runs of different envs are never averaged together (their returns differ).
  const auto groups = runs_by_env(curves);
  std::vector<FigurePanel> panels;
  for (const auto& [env, runs] : groups) {
    FigurePanel panel;
    panel.bands = mean_over_runs(runs, o.band == "std" ? Band::StdDev : Band::MinMax);
    const std::string env_name = env.empty() ? "(env unknown)" : env;
    panel.text.title = o.title.empty() ? env_name + ": " + metric.label
                                       : (groups.size() == 1 ? o.title : o.title + " (" + env_name + ")");
    panel.text.x_label = x_label(o.x);
    panel.text.y_label = metric.label;
    const bool several = std::any_of(panel.bands.begin(), panel.bands.end(), [](const CurveBand& b) { return b.runs > 1; });
    const bool cut = std::any_of(panel.bands.begin(), panel.bands.end(), [](const CurveBand& b) { return b.cut(); });
    if (several) panel.text.band_label = o.band == "std" ? "mean ± 1 std over runs" : "mean, min to max over runs";
    if (cut) panel.text.band_label += std::string(several ? ", " : "") + "to the shortest run";
    panels.push_back(std::move(panel));
  }
  write_figure(panels, o.out, o.width, o.height);

  std::printf("rdsim plot: %s from %zu run%s, %zu env%s (one panel each)\n", o.out.c_str(), dirs.size(),
              dirs.size() == 1 ? "" : "s", panels.size(), panels.size() == 1 ? "" : "s");
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const std::string& env = groups[p].first;
    for (const auto& b : panels[p].bands) {
      std::printf("  %s, %s (%d run%s): %s at %s %s: %.3f (band %.3f to %.3f)", env.empty() ? "(env unknown)" : env.c_str(),
                  b.algorithm.empty() ? "(algorithm unknown)" : b.algorithm.c_str(), b.runs, b.runs == 1 ? "" : "s",
                  metric.label.c_str(), o.x.c_str(), x_value(b.x.back()).c_str(), b.mean.back(), b.low.back(), b.high.back());
      if (b.cut())
        std::printf("; cut at the shortest run (the longest reached %s %s)", o.x.c_str(), x_value(b.longest_x).c_str());
      if (b.x.size() == 1) std::printf("; the runs share this one x only");
      std::printf("\n");
    }
  }
  return 0;
}

Command plot_command_entry() {
  return {"plot", "Draw the learning curves of runs (mean and band over each algorithm's runs) from their "
          "progress.csv (or, for another program's runs, episodes.csv), as PNG or SVG",
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
            cmd.add_option("--window", o->window,
                           "Runs without progress.csv (another program's, e.g. examples/sb3_her.py --log-dir): the "
                           "metric over this many last episodes of their episodes.csv")
                ->check(CLI::Range(1, 1000000))
                ->capture_default_str();
            cmd.add_option("--width", o->width, "Width in pixels")->check(CLI::Range(200, 8000))->capture_default_str();
            cmd.add_option("--height", o->height, "Height in pixels")->check(CLI::Range(150, 8000))->capture_default_str();
            return [o] { return plot_command(*o); };
          }};
}

}  // namespace rdsim
