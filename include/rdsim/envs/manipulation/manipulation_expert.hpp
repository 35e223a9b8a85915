#pragma once
#include <Eigen/Core>

#include "rdsim/core/env.hpp"
#include "rdsim/envs/scripted_expert.hpp"
#include "rdsim/envs/manipulation/manipulation_env.hpp"

// The scripted expert of the manipulation tasks (`rdsim demos record --expert`, the tests' success
// checks): it reads the env's privileged state (effector, cubes, goals, finger opening: not the
// observation) and emits the env's own Box actions. Each step it aims the effector at one point and
// sets the fingers, from the state (and the stack's stage and the last finger opening):
//   reach_goal      straight to the goal;
//   push            above the point behind the cube (seen from the goal), down to the table, then
//                   along the line to the goal; lifted and round again when the cube drifts off it;
//   pick_and_place  above the cube with the fingers open, down, close until the fingers hold it,
//                   then up and to the goal, squeezing;
//   stack           pick_and_place with the first cube to the first goal, open and rise, then the
//                   second cube to the second goal (on top of the first).
// A move is the remaining vector over effector_step, scaled down so that no axis exceeds 1. With
// control "joints" the expert gives the joint moves the env's IK would make for that move (all scaled
// down together when one exceeds joint_step).
namespace rdsim {

class ManipulationExpert : public ScriptedExpert {
public:
  // rdsim::Error naming the env when it is not a manipulation env.
  explicit ManipulationExpert(Env& env);

  void reset() override;   // call after each env reset
  Action act() override;   // the action for the env's current state

  Eigen::Vector3f aim() const { return aim_; }  // where the effector is heading (world frame)

  // This episode's first grasp (call after reset(); pick_and_place and stack) goes down `offset`
  // (m, world x and y) beside the first cube and closes the fingers there on nothing; then the
  // expert goes on as usual: up, over the cube and down again. The episode shows the way back from
  // a missed grasp. rdsim::Error for a task without a grasp.
  void miss_first_grasp(const Eigen::Vector2f& offset);
  bool grasps() const;  // the task grasps a cube (pick_and_place, stack)

private:
  Action plan();  // act() without the bookkeeping
  Action push();
  // Brings cube `k` to `goal`; true once it is there and held.
  Action carry(int k, const Eigen::Vector3f& goal);
  // The move towards `aim` (no axis above `largest`) and the fingers' opening (m; < 0: squeeze).
  Action action(const Eigen::Vector3f& aim, float opening, float largest = 1.0f);

  ManipulationEnv& env_;
  int stage_ = 0;  // stack: 0 first cube, 1 release and rise, 2 second cube
  float last_opening_ = 0.0f;  // m, the fingers' opening at the last act()
  Eigen::Vector3f aim_ = Eigen::Vector3f::Zero();
  bool missing_ = false;  // the first grasp still to be missed, miss_ beside the first cube
  Eigen::Vector2f miss_ = Eigen::Vector2f::Zero();
};

}  // namespace rdsim
