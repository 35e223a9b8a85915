// pick_and_place — a cube to a goal that is in the air half of the time (panda-gym's
// PandaPickAndPlace, Fetch's FetchPickAndPlace). The cube starts as push's; the goal lies at the task
// area centre + U(-1, 1) x goal_range in x and y, at the cube's resting height, raised by
// U(0, goal_height) (0.2 m) on half of the episodes. Actions Box(4): moves and the fingers' opening.
#include "rdsim/envs/manipulation/manipulation_env.hpp"

namespace rdsim {
namespace {

Placement draw_pick_and_place(const TaskArea& area, Rng& rng) {
  Placement p;
  Eigen::Vector3f goal = draw_on_area(area, area.goal_range, TaskArea::cube_size / 2.0f, rng);
  const float lift = static_cast<float>(rng.uniform(0.0, 1.0)) * area.goal_height;
  if (rng.uniform(0.0, 1.0) < 0.5) goal.z() += lift;
  p.goals = {goal};
  p.cubes = draw_cubes(area, 1, rng);
  return p;
}

}  // namespace

const ManipulationTask& pick_and_place_task() {
  static const ManipulationTask task{.name = "pick_and_place", .cubes = 1, .draw = draw_pick_and_place};
  return task;
}

EnvConfig pick_and_place_defaults() {
  return manipulation_env_config("pick_and_place", ManipulationOptions{.goal_height = 0.2});
}

std::unique_ptr<Env> make_pick_and_place(const EnvConfig& config) {
  return std::make_unique<ManipulationEnv>(pick_and_place_task(), config);
}

}  // namespace rdsim
