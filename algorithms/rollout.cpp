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

namespace {

// Acting on envs [first, end) at step t: the policy's actions for them, stored in the rollout.
class RolloutActor {
public:
  RolloutActor(VecEnv& vec, ActorCritic& policy, Rng& rng, RolloutBuffer& r)
      : vec_(vec), policy_(policy), rng_(rng), r_(r), actions_(static_cast<std::size_t>(r.envs)) {}

  const std::vector<Action>& act(int t, int first, int end) {
    const int n = end - first, base = t * r_.envs + first;
    const Eigen::MatrixXf& obs = network_input(vec_.observations(), pixels_scratch_, first, n);
    policy_.act(obs, false, rng_, act_);
    r_.observations.middleCols(base, n) = obs;
    r_.actions.middleCols(base, n) = act_.actions;
    r_.log_probs.segment(base, n) = act_.log_probs;
    r_.values.segment(base, n) = act_.values;
    for (int e = 0; e < n; ++e) actions_[static_cast<std::size_t>(first + e)] = policy_.env_action(act_.actions.col(e));
    return actions_;
  }

  // What envs [first, end) did at step t; truncated episodes get V(final observation), one
  // batched value pass over them.
  void store(int t, int first, int end, const std::vector<EnvStep>& steps) {
    const int base = t * r_.envs;
    truncated_.clear();
    for (int e = first; e < end; ++e) {
      const EnvStep& s = steps[static_cast<std::size_t>(e)];
      r_.rewards[base + e] = s.reward;
      r_.ends[static_cast<std::size_t>(base + e)] =
          s.terminated ? EpisodeEnd::Terminated : (s.truncated ? EpisodeEnd::Truncated : EpisodeEnd::None);
      if (s.bootstrap()) truncated_.push_back(e);
    }
    if (truncated_.empty()) return;
    Eigen::MatrixXf final_obs(policy_.observation_size(), static_cast<Eigen::Index>(truncated_.size()));
    for (std::size_t k = 0; k < truncated_.size(); ++k) {
      encode_observation(steps[static_cast<std::size_t>(truncated_[k])].final_observation, vec_.spec().observation,
                         final_obs.col(static_cast<Eigen::Index>(k)));
    }
    const Eigen::VectorXf v = policy_.predict_values(final_obs);
    for (std::size_t k = 0; k < truncated_.size(); ++k) r_.final_values[base + truncated_[k]] = v[static_cast<Eigen::Index>(k)];
  }

private:
  VecEnv& vec_;
  ActorCritic& policy_;
  Rng& rng_;
  RolloutBuffer& r_;
  Eigen::MatrixXf pixels_scratch_;
  ActBatch act_;
  std::vector<Action> actions_;
  std::vector<int> truncated_;
};

// Receives every group still in flight, dropping their errors: after an error the rollout is
// abandoned, and the VecEnv must be idle again for whatever the caller does next.
void drain(VecEnv& vec) {
  for (int g = 0; vec.in_flight() > 0; g = (g + 1) % vec.groups()) {
    try {
      vec.recv(g);
    } catch (...) {
    }
  }
}

}  // namespace

void collect_rollout(VecEnv& vec, ActorCritic& policy, Rng& rng, RolloutBuffer& r) {
  RolloutActor actor(vec, policy, rng, r);
  r.final_values.setZero();
  const int E = r.envs, G = vec.groups();
  if (G == 1) {
    for (int t = 0; t < r.steps; ++t) actor.store(t, 0, E, vec.step(actor.act(t, 0, E)));
  } else {
    // Group g's step t is sent as soon as the policy acted on it, and received (its results stored)
    // just before the policy acts on it again: meanwhile the workers step the other groups.
    try {
      for (int t = 0; t < r.steps; ++t) {
        for (int g = 0; g < G; ++g) {
          const int first = vec.group_first(g), end = vec.group_end(g);
          if (t > 0) actor.store(t - 1, first, end, vec.recv(g));
          vec.send(g, actor.act(t, first, end));
        }
      }
      for (int g = 0; g < G; ++g) actor.store(r.steps - 1, vec.group_first(g), vec.group_end(g), vec.recv(g));
    } catch (...) {
      drain(vec);
      throw;
    }
  }
  Eigen::MatrixXf pixels_scratch;
  r.last_values = policy.predict_values(network_input(vec.observations(), pixels_scratch));
}

}  // namespace rdsim
