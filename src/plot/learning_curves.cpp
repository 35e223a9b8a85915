#include "rdsim/plot/learning_curves.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "rdsim/core/csv_reader.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

namespace {

// Calls row(x, y) for every row of the CSV file with a finite value in both columns, in file order,
// reading it in pieces of about `piece_bytes`.
template <class Row>
void for_each_row(const std::string& path, const std::string& x_column, const std::string& y_column, std::size_t piece_bytes,
                  Row row) {
  CsvRows table = read_csv_rows(path, 0, piece_bytes);
  const int xi = csv_column(table.columns, x_column);
  const int yi = csv_column(table.columns, y_column);
  for (const auto& [index, name] : {std::pair{xi, x_column}, std::pair{yi, y_column}}) {
    if (index >= 0) continue;
    std::string known;
    for (const auto& c : table.columns) known += (known.empty() ? "" : ", ") + c;
    throw Error(path + ": no column \"" + name + "\" (it has: " + known + ")");
  }
  for (;;) {
    for (const auto& r : table.rows) {
      const double x = r[static_cast<std::size_t>(xi)], y = r[static_cast<std::size_t>(yi)];
      if (std::isfinite(x) && std::isfinite(y)) row(x, y);
    }
    if (!table.more) return;
    table = read_csv_rows(path, table.next, piece_bytes);
  }
}

}  // namespace

RunCurve read_run_curve(const std::string& dir, const std::string& x_column, const std::string& y_column,
                        std::size_t piece_bytes) {
  RunCurve run;
  run.info = read_run_info(dir);
  for_each_row((std::filesystem::path(dir) / progress_csv_name).string(), x_column, y_column, piece_bytes,
               [&](double x, double y) {
                 run.x.push_back(x);
                 run.y.push_back(y);
               });
  return run;
}

RunCurve read_episode_curve(const std::string& dir, const std::string& x_column, const std::string& y_column, int window,
                            std::size_t piece_bytes) {
  assert(window >= 1);
  RunCurve run;
  run.info = read_run_info(dir);
  std::vector<double> last(static_cast<std::size_t>(window));  // the last `window` values, a ring
  std::size_t count = 0;
  double sum = 0;  // of the values in the ring; recomputed each lap so that rounding never piles up
  for_each_row((std::filesystem::path(dir) / episodes_csv_name).string(), x_column, y_column, piece_bytes,
               [&](double x, double y) {
                 const std::size_t slot = count % last.size();
                 if (slot == 0 && count > 0) {
                   sum = 0;
                   for (double v : last) sum += v;
                 }
                 if (count >= last.size()) sum -= last[slot];
                 last[slot] = y;
                 sum += y;
                 ++count;
                 run.x.push_back(x);
                 run.y.push_back(sum / static_cast<double>(std::min(count, last.size())));
               });
  return run;
}

double interpolate(const RunCurve& run, double x) {
  const auto upper = std::lower_bound(run.x.begin(), run.x.end(), x);
  if (upper == run.x.begin()) return run.y.front();
  if (upper == run.x.end()) return run.y.back();
  const std::size_t i = static_cast<std::size_t>(upper - run.x.begin());
  const double x0 = run.x[i - 1], x1 = run.x[i];
  const double w = x1 > x0 ? (x - x0) / (x1 - x0) : 1.0;
  return run.y[i - 1] + w * (run.y[i] - run.y[i - 1]);
}

RunCurve crop_run_curve(const RunCurve& run, double x_max) {
  if (run.x.empty() || run.x.front() > x_max) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", x_max);
    throw Error(run.info.dir + ": no row at or below x = " + limit + " (--x-max cuts every curve there)");
  }
  RunCurve out;
  out.info = run.info;
  for (std::size_t i = 0; i < run.x.size() && run.x[i] <= x_max; ++i) {
    out.x.push_back(run.x[i]);
    out.y.push_back(run.y[i]);
  }
  if (out.x.back() < x_max && out.x.size() < run.x.size()) {
    out.x.push_back(x_max);
    out.y.push_back(interpolate(run, x_max));
  }
  return out;
}

std::vector<std::pair<std::string, std::vector<RunCurve>>> runs_by_env(const std::vector<RunCurve>& runs) {
  std::map<std::string, std::vector<RunCurve>> groups;
  for (const auto& run : runs) groups[run.info.env].push_back(run);
  return {groups.begin(), groups.end()};
}

std::vector<CurveBand> mean_over_runs(const std::vector<RunCurve>& runs, Band band, int points) {
  std::map<std::string, std::vector<const RunCurve*>> groups;
  for (const auto& run : runs) {
    if (run.x.empty()) throw Error(run.info.dir + ": no row with both values yet");
    if (run.info.env != runs.front().info.env) {
      throw Error(run.info.dir + ": its env (" + run.info.env + ") differs from " + runs.front().info.dir + "'s (" +
                  runs.front().info.env + "): runs of different envs are never averaged together");
    }
    groups[run.info.algorithm].push_back(&run);
  }
  std::vector<CurveBand> bands;
  for (const auto& [algorithm, members] : groups) {
    double first = -INFINITY, last = INFINITY, longest = -INFINITY;
    for (const RunCurve* r : members) {
      first = std::max(first, r->x.front());
      last = std::min(last, r->x.back());
      longest = std::max(longest, r->x.back());
    }
    if (first > last) {
      throw Error("the " + (algorithm.empty() ? std::string("unnamed") : algorithm) +
                  " runs share no range of x (one ends before another starts)");
    }
    CurveBand b;
    b.algorithm = algorithm;
    b.runs = static_cast<int>(members.size());
    b.longest_x = longest;
    const int n = first < last ? std::max(points, 2) : 1;
    std::vector<double> ys(members.size());
    for (int k = 0; k < n; ++k) {
      const double x = n == 1 ? first : first + (last - first) * k / (n - 1);
      for (std::size_t m = 0; m < members.size(); ++m) ys[m] = interpolate(*members[m], x);
      double mean = 0;
      for (double y : ys) mean += y;
      mean /= static_cast<double>(ys.size());
      double low = mean, high = mean;
      if (band == Band::MinMax) {
        low = *std::min_element(ys.begin(), ys.end());
        high = *std::max_element(ys.begin(), ys.end());
      } else if (ys.size() > 1) {
        double ss = 0;
        for (double y : ys) ss += (y - mean) * (y - mean);
        const double sd = std::sqrt(ss / static_cast<double>(ys.size() - 1));  // sample standard deviation
        low = mean - sd;
        high = mean + sd;
      }
      b.x.push_back(x);
      b.mean.push_back(mean);
      b.low.push_back(low);
      b.high.push_back(high);
    }
    bands.push_back(std::move(b));
  }
  return bands;
}

}  // namespace rdsim
