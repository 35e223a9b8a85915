#pragma once
#include <Eigen/Core>

#include "rdsim/core/env.hpp"
#include "rdsim/envs/scripted_expert.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"

// The scripted expert of the reaching envs (`rdsim demos record --expert`): a planner that reads the
// env's privileged state (end-effector and target positions in the world from ReachTask, not the
// observation) and emits the env's own actions, so its demonstrations look exactly like a person's.
//
// Plan: visit the task's route (ReachTerms::expert_route: world points, e.g. the way round
// jaka_obstacle's column) in order, then the approach point (target + ReachTerms::expert_approach,
// when set: the side to arrive from), then go straight to the target. A point counts as passed once
// the end effector is within `route_tolerance` of it. Each step:
//   Discrete(6): the move along the axis with the largest remaining distance to the current aim
//                (the env's -x, +x, -y, +y, -z, +z);
//   Box(3):      the remaining vector scaled so that its longest axis is at most 1 (a full move):
//                its direction kept, divided by action_step when closer than one move.
namespace rdsim {

class ReachExpert : public ScriptedExpert {
public:
  // rdsim::Error naming the env when it is not a reaching env (only those have an expert).
  explicit ReachExpert(Env& env);

  // Call after each env reset: starts the route again.
  void reset() override;
  // The action for the env's current state.
  Action act() override;

  // Where the expert is heading now (world frame).
  Eigen::Vector3f aim() const;

  static constexpr float route_tolerance = 0.03f;  // m

private:
  std::size_t points() const;  // route points, plus the approach point if any

  ReachEnv& env_;
  std::size_t next_point_ = 0;
};

}  // namespace rdsim
