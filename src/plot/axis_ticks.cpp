#include "axis_ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rdsim {

Ticks nice_ticks(double low, double high, int target, bool widen) {
  if (!(high > low)) {
    const double pad = std::abs(low) > 0 ? std::abs(low) * 0.1 : 1.0;
    low -= pad;
    high += pad;
  }
  const double raw = (high - low) / std::max(target - 1, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude * 10;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  }
  Ticks t;
  t.step = step;
  const double first = std::ceil(low / step - 1e-9) * step, last = std::floor(high / step + 1e-9) * step;
  t.low = widen ? std::min(low, first - (first > low + 1e-9 * step ? step : 0)) : low;
  t.high = widen ? std::max(high, last + (last < high - 1e-9 * step ? step : 0)) : high;
  if (widen) {
    t.low = std::floor(t.low / step + 1e-9) * step;
    t.high = std::ceil(t.high / step - 1e-9) * step;
  }
  for (double v = std::ceil(t.low / step - 1e-9) * step; v <= t.high + step * 1e-6; v += step) {
    t.values.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return t;
}

std::string tick_label(double value, double step) {
  if (value == 0) return "0";
  const char* suffix = "";
  double scale = 1;
  const double big = std::max(std::abs(value), step);
  if (big >= 1e6 && step >= 1e5) {
    suffix = "M";
    scale = 1e6;
  } else if (big >= 1e3 && step >= 1e2) {
    suffix = "k";
    scale = 1e3;
  }
  // As many decimals as the step needs (0.25 -> 2, 2.5 -> 1, 50 -> 0).
  int decimals = 0;
  for (double s = step / scale; decimals < 6 && std::abs(s - std::round(s)) > 1e-6 * std::max(1.0, s); s *= 10) ++decimals;
  char text[48];
  std::snprintf(text, sizeof text, "%.*f%s", decimals, value / scale, suffix);
  return text;
}

}  // namespace rdsim
