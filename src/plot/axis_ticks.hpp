#pragma once
#include <string>
#include <vector>

// Axis ticks at "nice" numbers (1, 2 or 5 times a power of ten) and their labels.
namespace rdsim {

struct Ticks {
  double low = 0, high = 1;      // the axis range
  double step = 1;
  std::vector<double> values;    // the multiples of step from low to high
};

// About `target` ticks over [low, high] (an empty range is widened around its value). The range
// stays as given; with widen, it grows to whole steps.
Ticks nice_ticks(double low, double high, int target = 6, bool widen = false);

// "250k", "1.5M", "0.25", "-40": short, and exact at the tick step.
std::string tick_label(double value, double step);

}  // namespace rdsim
