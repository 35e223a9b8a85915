#include "rdsim/core/goal_layout.hpp"

#include <cmath>

namespace rdsim {

bool GoalLayout::is_success(const float* achieved, const float* desired) const {
  const float limit = distance_threshold * distance_threshold;
  for (int p = 0; p < points; ++p) {
    float d2 = 0.0f;
    for (int i = 3 * p; i < 3 * p + 3; ++i) d2 += (achieved[i] - desired[i]) * (achieved[i] - desired[i]);
    if (!(d2 < limit)) return false;
  }
  return true;
}

float GoalLayout::reward_of(const float* achieved, const float* desired) const {
  if (reward == GoalReward::Sparse) return is_success(achieved, desired) ? 0.0f : -1.0f;
  float d2 = 0.0f;
  for (int i = 0; i < goal_size(); ++i) d2 += (achieved[i] - desired[i]) * (achieved[i] - desired[i]);
  return -std::sqrt(d2);
}

void GoalLayout::compute_reward(const float* achieved, const float* desired, int n, float* out) const {
  const int g = goal_size();
  for (int i = 0; i < n; ++i) out[i] = reward_of(achieved + i * g, desired + i * g);
}

}  // namespace rdsim
