#include "rdsim/envs/manipulation/manipulation_task.hpp"

namespace rdsim {

Eigen::Vector3f draw_on_area(const TaskArea& area, float range, float z, Rng& rng) {
  const float x = area.centre.x() + static_cast<float>(rng.uniform(-1.0, 1.0)) * range;  // two statements:
  const float y = area.centre.y() + static_cast<float>(rng.uniform(-1.0, 1.0)) * range;  // the draws' order
  return {x, y, z};
}

std::vector<Eigen::Vector3f> draw_cubes(const TaskArea& area, int n, Rng& rng) {
  constexpr float kApart = 1.5f * TaskArea::cube_size;  // m between cube centres
  constexpr int kTries = 100;
  std::vector<Eigen::Vector3f> cubes;
  for (int k = 0; k < n; ++k) {
    Eigen::Vector3f c;
    for (int t = 0; t < kTries; ++t) {
      c = draw_on_area(area, area.object_range, TaskArea::cube_size / 2.0f, rng);
      bool clear = true;
      for (const Eigen::Vector3f& other : cubes) clear = clear && (c - other).norm() >= kApart;
      if (clear) break;
    }
    cubes.push_back(c);
  }
  return cubes;
}

}  // namespace rdsim
