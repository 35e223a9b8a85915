#include "rdsim/algorithms/advantage.hpp"

#include <cmath>

namespace rdsim {

void compute_gae(RolloutBuffer& r, float gamma, float gae_lambda) {
  const int T = r.steps, E = r.envs;
  r.advantages.resize(T * E);
  r.returns.resize(T * E);
  for (int e = 0; e < E; ++e) {
    float next_value = r.last_values[e];
    float next_advantage = 0.0f;  // of step t+1, valid while the episode continues
    bool continues = true;        // step t+1 belongs to the same episode as step t
    for (int t = T - 1; t >= 0; --t) {
      const int i = t * E + e;
      const EpisodeEnd end = r.ends[static_cast<std::size_t>(i)];
      float bootstrap = next_value;
      if (end == EpisodeEnd::Terminated) {
        bootstrap = 0.0f;
        continues = false;
      } else if (end == EpisodeEnd::Truncated) {
        bootstrap = r.final_values[i];
        continues = false;
      }
      const float delta = r.rewards[i] + gamma * bootstrap - r.values[i];
      const float advantage = delta + (continues ? gamma * gae_lambda * next_advantage : 0.0f);
      r.advantages[i] = advantage;
      r.returns[i] = advantage + r.values[i];
      next_value = r.values[i];
      next_advantage = advantage;
      continues = true;
    }
  }
}

}  // namespace rdsim

namespace rdsim {

double explained_variance(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target) {
  const Eigen::ArrayXd y = target.cast<double>().array();
  const Eigen::ArrayXd d = y - prediction.cast<double>().array();
  const double var_y = (y - y.mean()).square().mean();
  if (var_y <= 0.0) return 0.0;
  return 1.0 - (d - d.mean()).square().mean() / var_y;
}

void normalize_advantages(Eigen::VectorXf& adv) {
  const Eigen::Index n = adv.size();
  if (n < 2) return;
  const float mean = adv.mean();
  const float stddev = std::sqrt((adv.array() - mean).square().sum() / static_cast<float>(n - 1));
  adv = (adv.array() - mean) / (stddev + 1e-8f);
}

}  // namespace rdsim
