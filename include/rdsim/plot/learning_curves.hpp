#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "rdsim/core/run_files.hpp"

// The data of a learning-curve figure, from the runs' progress.csv (or, for other programs' runs,
// episodes.csv): each run's metric against an x column, and per algorithm the mean and a band over its runs (its seeds).
namespace rdsim {

// One run's curve: the rows where both columns have a value, in file order.
struct RunCurve {
  RunInfo info;
  std::vector<double> x, y;
};

// Reads <dir>/progress.csv, the whole of it in pieces of about `piece_bytes` (a 1M-step SAC run
// logs some 80 MB). Throws rdsim::Error naming the file when it cannot be read, or naming the
// column (and listing those there are) when it has no such column.
RunCurve read_run_curve(const std::string& dir, const std::string& x_column, const std::string& y_column,
                        std::size_t piece_bytes = 64 * 1024 * 1024);

// A run of another program that writes only an episodes.csv in rdsim's columns (episode, timesteps,
// return, length, success, wall_time: examples/sb3_her.py --log-dir): after each episode, the mean
// of y_column over the last `window` episodes (over those there are, before the first `window`, as
// progress.csv's statistics), against that row's x_column. Errors as read_run_curve's.
RunCurve read_episode_curve(const std::string& dir, const std::string& x_column, const std::string& y_column, int window,
                            std::size_t piece_bytes = 64 * 1024 * 1024);

enum class Band { StdDev, MinMax };

// One algorithm's runs on a common grid of x: mean, and the band (mean ± one standard deviation over
// runs, or min..max). The grid spans only the x every run reached (from the largest first x to the
// smallest last x), so each point averages all runs; between rows a run is linearly interpolated.
struct CurveBand {
  std::string algorithm;  // config.json's algorithm ("ppo"); "" when unknown
  int runs = 0;
  std::vector<double> x, mean, low, high;
  // The last x of the run that went furthest: above x.back() when the runs have different lengths
  // and the band was cut at the shortest one (say so: the longer runs' ends are not drawn).
  double longest_x = 0;
  bool cut() const { return !x.empty() && longest_x > x.back(); }
};

// Groups runs by algorithm (bands sorted by algorithm name) and averages each group on `points`
// grid points. Throws rdsim::Error when a run has no values or a group's runs share no x range,
// and when the runs are of different envs (their returns are not comparable: split them with
// runs_by_env first).
std::vector<CurveBand> mean_over_runs(const std::vector<RunCurve>& runs, Band band = Band::StdDev, int points = 300);

// The runs of each env (config.json's env.name; "" when unknown), envs in name order, runs in
// their given order: one figure panel per env.
std::vector<std::pair<std::string, std::vector<RunCurve>>> runs_by_env(const std::vector<RunCurve>& runs);

// The run's curve up to x_max: its rows with x <= x_max, then (when the run went further) its value at
// x_max, interpolated. Throws rdsim::Error naming the run when its first row is already past x_max.
RunCurve crop_run_curve(const RunCurve& run, double x_max);

// A run's y at x by linear interpolation between the rows around it (x must lie in the run's range;
// x ascending, as progress.csv is).
double interpolate(const RunCurve& run, double x);

}  // namespace rdsim
