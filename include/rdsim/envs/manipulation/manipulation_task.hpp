#pragma once
#include <Eigen/Core>
#include <vector>

#include "rdsim/core/rng.hpp"

// The task half of a manipulation env (panda-gym's split of robot and task): how many cubes stand on
// the table and where each episode puts them and the goal. Everything else (the arm, the gripper,
// the observation, the reward and the episode rules) is ManipulationEnv's, shared by every task, so
// a task is this description and its draw function, one file each (push.cpp, pick_and_place.cpp,
// stack.cpp, reach_goal.cpp).
namespace rdsim {

// Where things are drawn (world frame, metres; the table top is z = 0).
struct TaskArea {
  Eigen::Vector2f centre = Eigen::Vector2f::Zero();  // ManipulationOptions::area_centre
  float object_range = 0.0f;  // half-ranges in x and y (ManipulationOptions)
  float goal_range = 0.0f;
  float goal_height = 0.0f;
  float lowest_effector = 0.0f;  // the lowest effector height the workspace allows (reach_goal)
  static constexpr float cube_size = 0.04f;  // m, the cubes' edge (assets/objects/cube_*.urdf)
};

// One episode's start: the cubes' centres and the goal points (as many as the task's goal has).
struct Placement {
  std::vector<Eigen::Vector3f> cubes;
  std::vector<Eigen::Vector3f> goals;
};

struct ManipulationTask {
  const char* name = "";
  int cubes = 0;  // 0: the goal is the effector's position (reach_goal)
  // The episode's placement, from the env's random stream only.
  Placement (*draw)(const TaskArea& area, Rng& rng) = nullptr;
};

// Helpers the tasks' draw functions share.
// A point of the task area: centre + U(-1, 1) x range in x and y, at height z.
Eigen::Vector3f draw_on_area(const TaskArea& area, float range, float z, Rng& rng);
// `n` cube centres resting on the table, each at least 1.5 cube edges from the others (drawn again
// until so, at most 100 times; then the last draw stands).
std::vector<Eigen::Vector3f> draw_cubes(const TaskArea& area, int n, Rng& rng);

// The four tasks (their files).
const ManipulationTask& push_task();
const ManipulationTask& pick_and_place_task();
const ManipulationTask& stack_task();
const ManipulationTask& reach_goal_task();

}  // namespace rdsim
