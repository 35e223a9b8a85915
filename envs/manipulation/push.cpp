// push — a cube on the table to a goal on the table, the gripper closed (panda-gym's PandaPush,
// Fetch's FetchPush). The cube starts at the task area centre + U(-1, 1) x object_range in x and y;
// the goal at the centre + U(-1, 1) x goal_range, on the table (the cube's centre height). Actions
// Box(3) (block_gripper); everything else is ManipulationEnv's (envs/manipulation/manipulation_env.hpp).
#include "rdsim/envs/manipulation/manipulation_env.hpp"

namespace rdsim {
namespace {

Placement draw_push(const TaskArea& area, Rng& rng) {
  Placement p;
  p.goals = {draw_on_area(area, area.goal_range, TaskArea::cube_size / 2.0f, rng)};
  p.cubes = draw_cubes(area, 1, rng);
  return p;
}

}  // namespace

const ManipulationTask& push_task() {
  static const ManipulationTask task{.name = "push", .cubes = 1, .draw = draw_push};
  return task;
}

EnvConfig push_defaults() { return manipulation_env_config("push", ManipulationOptions{.block_gripper = true}); }

std::unique_ptr<Env> make_push(const EnvConfig& config) { return std::make_unique<ManipulationEnv>(push_task(), config); }

}  // namespace rdsim
