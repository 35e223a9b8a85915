#pragma once
#include "rdsim/core/config_fields.hpp"

// The "her" object of a training config: hindsight experience replay (Andrychowicz et al. 2017)
// for the off-policy algorithms (sac, td3, ddpg, and dqn with one-step returns) on goal-conditioned
// envs (core/goal_layout.hpp).
// A minibatch keeps 1 / (n_sampled_goal + 1) of its transitions as they were; the others get a
// goal that was achieved later in their own episode (hindsight_replay.hpp), with the reward the
// env's goal layout gives for it: SB3's HerReplayBuffer, relabelled when sampled.
namespace rdsim {

enum class GoalSelection { Future, Final, Episode };

struct HerConfig {
  int n_sampled_goal = 4;
  GoalSelection goal_selection_strategy = GoalSelection::Future;

  // The share of a minibatch that is relabelled: n / (n + 1).
  double relabel_fraction() const { return n_sampled_goal / (n_sampled_goal + 1.0); }
};

inline const config::Names<GoalSelection>& goal_selection_names() {
  static const config::Names<GoalSelection> names = {
      {"future", GoalSelection::Future}, {"final", GoalSelection::Final}, {"episode", GoalSelection::Episode}};
  return names;
}

template <class V, class C>
  requires config::Describes<C, HerConfig>
void describe(V& v, C& c) {
  v.field("n_sampled_goal", c.n_sampled_goal, config::Range{1, 100},
          "relabelled transitions per real one: n / (n + 1) of every minibatch gets a goal achieved in hindsight");
  v.choice("goal_selection_strategy", c.goal_selection_strategy, goal_selection_names(),
           "future: achieved at this step or later in the episode; final: at the episode's last step; episode: "
           "at any step of it");
}

}  // namespace rdsim
