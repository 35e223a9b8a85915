// stack — two cubes, the first (blue) to a goal on the table, the second (green) on top of it
// (panda-gym's PandaStack). Both cubes start on the task area (centre + U(-1, 1) x object_range in x
// and y, at least 6 cm apart); the first goal lies at the centre + U(-1, 1) x goal_range on the
// table, the second one cube edge (4 cm) above it. Actions Box(4). Success needs both cubes within
// distance_threshold of their goals; the dense reward is minus the distance between the two 6-value
// vectors (panda-gym's). Episodes last 100 steps (panda-gym's PandaStack-v3: two cubes to carry, where
// push and pick_and_place have one in 50).
#include "rdsim/envs/manipulation/manipulation_env.hpp"

namespace rdsim {
namespace {

Placement draw_stack(const TaskArea& area, Rng& rng) {
  Placement p;
  const Eigen::Vector3f first = draw_on_area(area, area.goal_range, TaskArea::cube_size / 2.0f, rng);
  p.goals = {first, first + Eigen::Vector3f(0.0f, 0.0f, TaskArea::cube_size)};
  p.cubes = draw_cubes(area, 2, rng);
  return p;
}

}  // namespace

const ManipulationTask& stack_task() {
  static const ManipulationTask task{.name = "stack", .cubes = 2, .draw = draw_stack};
  return task;
}

EnvConfig stack_defaults() {
  EnvConfig c = manipulation_env_config("stack", ManipulationOptions{});
  c.max_steps = 100;
  return c;
}

std::unique_ptr<Env> make_stack(const EnvConfig& config) { return std::make_unique<ManipulationEnv>(stack_task(), config); }

}  // namespace rdsim
