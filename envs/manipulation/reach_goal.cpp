// reach_goal — the reaching task in goal-conditioned form (panda-gym's PandaReach, Fetch's
// FetchReach): the effector to a goal point, for a quick check of hindsight experience replay. No
// cube; the goal lies at the task area centre + U(-1, 1) x goal_range in x and y and U(0, goal_height)
// above the lowest effector height (workspace_min's z); achieved_goal is the effector's position.
// Actions Box(3) (block_gripper).
#include "rdsim/envs/manipulation/manipulation_env.hpp"

namespace rdsim {
namespace {

Placement draw_reach_goal(const TaskArea& area, Rng& rng) {
  Eigen::Vector3f goal = draw_on_area(area, area.goal_range, area.lowest_effector, rng);
  goal.z() += static_cast<float>(rng.uniform(0.0, 1.0)) * area.goal_height;
  return Placement{.cubes = {}, .goals = {goal}};
}

}  // namespace

const ManipulationTask& reach_goal_task() {
  static const ManipulationTask task{.name = "reach_goal", .cubes = 0, .draw = draw_reach_goal};
  return task;
}

EnvConfig reach_goal_defaults() {
  return manipulation_env_config("reach_goal", ManipulationOptions{.block_gripper = true, .goal_height = 0.25});
}

std::unique_ptr<Env> make_reach_goal(const EnvConfig& config) {
  return std::make_unique<ManipulationEnv>(reach_goal_task(), config);
}

}  // namespace rdsim
