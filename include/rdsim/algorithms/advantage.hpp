#pragma once
#include "rdsim/algorithms/rollout.hpp"

namespace rdsim {

// Generalised advantage estimation (Schulman et al. 2016) over a filled rollout, per env,
// backwards in time. At a step that ended its episode the trace restarts; a terminated step
// has no next value, a truncated one bootstraps from final_values (V of the observation that
// ended it). The last step of the rollout bootstraps from last_values. gae_lambda == 1 gives
// plain n-step returns (A2C). Writes rollout.advantages and rollout.returns (= adv + V).
void compute_gae(RolloutBuffer& rollout, float gamma, float gae_lambda);

}  // namespace rdsim

namespace rdsim {

// 1 - Var(target - prediction) / Var(target): 1 for a perfect value function, 0 for a constant
// one, negative when worse than a constant; 0 when the target does not vary.
double explained_variance(const Eigen::VectorXf& prediction, const Eigen::VectorXf& target);

// Advantages standardised over a batch: (a - mean) / (sample standard deviation + 1e-8); a batch
// of fewer than 2 is left as it is.
void normalize_advantages(Eigen::VectorXf& advantages);

}  // namespace rdsim
