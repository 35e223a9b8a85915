#include "rdsim/core/goal_layout.hpp"

#include <cmath>

namespace rdsim {

namespace {

// Goal points of `achieved` that are not within `threshold` of their desired points.
int points_missed(const float* achieved, const float* desired, int points, float threshold) {
  const float limit = threshold * threshold;
  int missed = 0;
  for (int p = 0; p < points; ++p) {
    float d2 = 0.0f;
    for (int i = 3 * p; i < 3 * p + 3; ++i) d2 += (achieved[i] - desired[i]) * (achieved[i] - desired[i]);
    missed += !(d2 < limit);
  }
  return missed;
}

}  // namespace

std::optional<GoalReward> goal_reward_from_string(const std::string& name) {
  for (GoalReward r : {GoalReward::Sparse, GoalReward::Partial, GoalReward::Dense})
    if (name == to_string(r)) return r;
  return std::nullopt;
}

bool GoalLayout::is_success(const float* achieved, const float* desired) const {
  return points_missed(achieved, desired, points, distance_threshold) == 0;
}

float GoalLayout::reward_of(const float* achieved, const float* desired) const {
  if (reward == GoalReward::Sparse) return is_success(achieved, desired) ? 0.0f : -1.0f;
  if (reward == GoalReward::Partial)
    return -static_cast<float>(points_missed(achieved, desired, points, distance_threshold)) / static_cast<float>(points);
  float d2 = 0.0f;
  for (int i = 0; i < goal_size(); ++i) d2 += (achieved[i] - desired[i]) * (achieved[i] - desired[i]);
  return -std::sqrt(d2);
}

void GoalLayout::compute_reward(const float* achieved, const float* desired, int n, float* out) const {
  const int g = goal_size();
  for (int i = 0; i < n; ++i) out[i] = reward_of(achieved + i * g, desired + i * g);
}

}  // namespace rdsim
