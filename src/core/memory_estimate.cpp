#include "rdsim/core/memory_estimate.hpp"

#include <algorithm>
#include <cstdio>

namespace rdsim {

void MemoryEstimate::add(std::string what, double bytes) {
  if (bytes > 0.0) items_.push_back({std::move(what), bytes});
}

double MemoryEstimate::total() const {
  double sum = 0.0;
  for (const auto& i : items_) sum += i.bytes;
  return sum;
}

std::string MemoryEstimate::summary(std::size_t max_items) const {
  std::vector<MemoryItem> sorted = items_;
  std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.bytes > b.bytes; });
  std::string s = "about " + format_bytes(total());
  for (std::size_t i = 0; i < sorted.size() && i < max_items; ++i)
    s += (i == 0 ? ": " : ", ") + sorted[i].what + " " + format_bytes(sorted[i].bytes);
  if (sorted.size() > max_items) s += ", ...";
  return s;
}

std::string format_bytes(double bytes) {
  static const char* units[] = {"B", "KB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 999.5 && u < 6) {
    bytes /= 1000.0;
    ++u;
  }
  char buf[48];
  if (bytes >= 999.5)
    std::snprintf(buf, sizeof buf, "%.3g %s", bytes, units[u]);
  else
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return buf;
}

}  // namespace rdsim
