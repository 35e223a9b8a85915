#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rdsim/core/rng.hpp"

// On-policy experience from several envs: `steps` VecEnv steps of `envs` envs. Sample i of
// step t and env e is i = t * envs + e (columns of the matrices, entries of the vectors).
namespace rdsim {

class ActorCritic;
class VecEnv;

enum class EpisodeEnd : std::uint8_t { None = 0, Terminated = 1, Truncated = 2 };

struct RolloutBuffer {
  int steps = 0, envs = 0;
  Eigen::MatrixXf observations;  // obs_size x (steps*envs), policy input encoding
  Eigen::MatrixXf actions;       // action_dim x (steps*envs); discrete index stored as float
  Eigen::VectorXf log_probs;     // log pi(a|s) when acting
  Eigen::VectorXf values;        // V(s) when acting
  Eigen::VectorXf rewards;
  std::vector<EpisodeEnd> ends;  // how the episode ended at this step, if it did
  Eigen::VectorXf final_values;  // V(final observation) where ends == Truncated, else 0
  Eigen::VectorXf last_values;   // envs: V of each env's observation after the last step
  Eigen::VectorXf advantages;    // filled by compute_gae
  Eigen::VectorXf returns;

  void resize(int steps, int envs, int obs_size, int action_dim);
  int size() const { return steps * envs; }
};

// Fills `rollout` (already resized) by acting with `policy` in `vec_env`, sampling actions with
// `rng`. Truncated episodes get V(final observation) in final_values; terminated ones do not.
void collect_rollout(VecEnv& vec_env, ActorCritic& policy, Rng& rng, RolloutBuffer& rollout);

}  // namespace rdsim
