#pragma once
#include "rdsim/core/config_fields.hpp"

// jaka_obstacle's own options (besides the reaching tasks' ReachOptions): how its column moves and
// which reward rule it pays. One option group (core/env_options.hpp) in jaka_obstacle's defaults;
// envs/reaching/jaka_obstacle.cpp and envs/reaching/reach_env.cpp (ReachTerms) implement them.
namespace rdsim {

enum class ColumnMotion { Static, RandomWalk };
enum class RewardRule { NegativeDistance, InverseDistance };

struct ObstacleOptions {
  ColumnMotion column_motion = ColumnMotion::Static;
  RewardRule reward = RewardRule::NegativeDistance;
};

inline const config::Names<ColumnMotion>& column_motion_names() {
  static const config::Names<ColumnMotion> names = {{"static", ColumnMotion::Static},
                                                    {"random_walk", ColumnMotion::RandomWalk}};
  return names;
}
inline const config::Names<RewardRule>& reward_rule_names() {
  static const config::Names<RewardRule> names = {{"negative_distance", RewardRule::NegativeDistance},
                                                  {"inverse_distance", RewardRule::InverseDistance}};
  return names;
}

template <class V, class C>
  requires config::Describes<C, ObstacleOptions>
void describe(V& v, C& c) {
  v.choice("column_motion", c.column_motion, column_motion_names(),
           "the obstacle column: static, or random_walk (each env step it moves by U(-3, 3) mm in x and y, "
           "staying within 5 cm of its place; back there at reset)");
  v.choice("reward", c.reward, reward_rule_names(),
           "negative_distance (-distance per step; touching the column: -200 and the end) or "
           "inverse_distance (RobotDrlSim's obstacle env: 1/max(distance, 1 cm) - 2 t/max_steps per step, "
           "-10 on each step touching the column (the episode goes on), +10 on each step within 0.1 m)");
}

}  // namespace rdsim
