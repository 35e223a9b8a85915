#pragma once
#include <optional>
#include <string>

// Goal-conditioned observations (Gymnasium-Robotics' GoalEnv): one Float32 observation vector read
// as three named slices, in this order,
//     [ observation (the robot and the objects) | achieved_goal | desired_goal ],
// and the reward a goal env gives for any (achieved, desired) pair, as plain data of the env's spec
// so that hindsight experience replay can relabel stored transitions without the env (the C++
// algorithms, VecEnv, the Python Dict spaces and the remote link all read this one declaration).
//
// A goal is `points` 3-D points (a cube's centre, the end effector; stack: two cubes), so
// achieved == desired == 3 x points values.
namespace rdsim {

enum class GoalReward { Sparse, Partial, Dense };

struct GoalLayout {
  int observation = 0;  // values of the "observation" slice (first)
  int points = 0;       // 3-D points in a goal; 0 = not a goal-conditioned env
  float distance_threshold = 0.05f;  // m: a goal point closer than this to its desired point is reached
  // Sparse: -1 until every goal point is within distance_threshold of its desired point, then 0.
  // Partial: minus the share of goal points not within it (stack: -1, -0.5 with one cube on its
  // goal, 0): Nair et al. 2018's step reward, the same as Sparse for one point.
  // Dense: minus the Euclidean distance between the whole achieved and desired vectors (panda-gym's).
  GoalReward reward = GoalReward::Sparse;

  bool active() const { return points > 0; }
  int goal_size() const { return 3 * points; }                  // achieved_goal = desired_goal values
  int achieved_offset() const { return observation; }           // where achieved_goal starts
  int desired_offset() const { return observation + goal_size(); }
  int size() const { return observation + 2 * goal_size(); }    // the whole observation vector

  // Whether every goal point of `achieved` is within distance_threshold of its desired point
  // (goal_size() values each).
  bool is_success(const float* achieved, const float* desired) const;
  // The reward of one (achieved, desired) pair: what step() returns for it.
  float reward_of(const float* achieved, const float* desired) const;
  // `n` rewards: row i of `achieved` and `desired` (each n x goal_size(), row-major) into out[i].
  void compute_reward(const float* achieved, const float* desired, int n, float* out) const;
};

inline const char* to_string(GoalReward r) {
  return r == GoalReward::Sparse ? "sparse" : r == GoalReward::Partial ? "partial" : "dense";
}
// The reward named `name` (to_string's names); none for any other string.
std::optional<GoalReward> goal_reward_from_string(const std::string& name);

}  // namespace rdsim
