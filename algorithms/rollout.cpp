#include "rdsim/algorithms/rollout.hpp"

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"

namespace rdsim {

void RolloutBuffer::resize(int n_steps, int n_envs, int obs_size, int action_dim) {
  steps = n_steps;
  envs = n_envs;
  const int n = n_steps * n_envs;
  observations.resize(obs_size, n);
  actions.resize(action_dim, n);
  log_probs.resize(n);
  values.resize(n);
  rewards.resize(n);
  ends.assign(static_cast<std::size_t>(n), EpisodeEnd::None);
  final_values.setZero(n);
  last_values.resize(n_envs);
  advantages.resize(n);
  returns.resize(n);
}

void collect_rollout(VecEnv& vec, ActorCritic& policy, Rng& rng, RolloutBuffer& r) {
  const ObservationSpace& space = vec.spec().observation;
  const int E = r.envs;
  Eigen::MatrixXf pixels_scratch;
  ActBatch act;
  std::vector<Action> actions(static_cast<std::size_t>(E));
  std::vector<int> truncated;
  r.final_values.setZero();
  for (int t = 0; t < r.steps; ++t) {
    const Eigen::MatrixXf& obs = network_input(vec.observations(), pixels_scratch);
    policy.act(obs, false, rng, act);
    const int base = t * E;
    r.observations.middleCols(base, E) = obs;
    r.actions.middleCols(base, E) = act.actions;
    r.log_probs.segment(base, E) = act.log_probs;
    r.values.segment(base, E) = act.values;
    for (int e = 0; e < E; ++e) actions[static_cast<std::size_t>(e)] = policy.env_action(act.actions.col(e));

    const std::vector<EnvStep>& steps = vec.step(actions);
    truncated.clear();
    for (int e = 0; e < E; ++e) {
      const EnvStep& s = steps[static_cast<std::size_t>(e)];
      r.rewards[base + e] = s.reward;
      r.ends[static_cast<std::size_t>(base + e)] =
          s.terminated ? EpisodeEnd::Terminated : (s.truncated ? EpisodeEnd::Truncated : EpisodeEnd::None);
      if (s.bootstrap()) truncated.push_back(e);
    }
    if (!truncated.empty()) {
      // One batched value pass over the observations that ended truncated episodes.
      Eigen::MatrixXf final_obs(policy.observation_size(), static_cast<Eigen::Index>(truncated.size()));
      for (std::size_t k = 0; k < truncated.size(); ++k) {
        encode_observation(steps[static_cast<std::size_t>(truncated[k])].final_observation, space,
                           final_obs.col(static_cast<Eigen::Index>(k)));
      }
      const Eigen::VectorXf v = policy.predict_values(final_obs);
      for (std::size_t k = 0; k < truncated.size(); ++k) r.final_values[base + truncated[k]] = v[static_cast<Eigen::Index>(k)];
    }
  }
  r.last_values = policy.predict_values(network_input(vec.observations(), pixels_scratch));
}

}  // namespace rdsim
