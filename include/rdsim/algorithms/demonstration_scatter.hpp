#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// Scattering what a demonstrated step does not depend on (demonstrations.scatter): a data
// augmentation of the demonstrated transitions of a goal env with objects (push, pick_and_place,
// stack), against learning a few demonstrated layouts by heart.
//
// In a demonstration, an object is *idle* at a step when it has not moved yet and is not the next
// one the demonstrator moves (stack: the second cube while the first is fetched and placed), and
// the goal is idle while no object has moved yet. The demonstrated action would have been the same
// with an idle object elsewhere on the table, clear of the effector and of the other objects, and,
// where the way to the first object does not depend on where it is to go (the scripted expert's
// pick_and_place and stack, not push, which lines up behind the cube; `goal`), with an idle goal
// elsewhere: a scattered transition moves each idle object (its position, its position from the
// effector and its achieved-goal point) to a new place drawn in the rectangle where the
// demonstrations' objects started, and an idle goal (every desired point together) to one drawn
// where their goals were, in both observations of the transition alike. A desired point that an
// object meets where it lies (hindsight goals) moves with it. The reward and `terminated` are
// computed again from the goals. Velocities, orientations, the finger opening and the action stay.
namespace rdsim {

struct DemoFile;  // demos/demo_file.hpp

class DemonstrationScatter {
public:
  // The objects of `spec`'s observation (each part "NAME_position" of 3 values but the
  // effector's, with "NAME_from_effector" where the env has it), which of them are idle at each
  // step of `demos` (one slot per step, in the file's order, as DemonstrationReplay stores them),
  // and where the demonstrations placed objects and goals. Needs supported(spec) (checked by the
  // caller). `goal`: scatter an idle goal too.
  DemonstrationScatter(const DemoFile& demos, const Spec& spec, bool goal);

  // A goal env with one to seven object positions in its (Float32) observation.
  static bool supported(const Spec& spec);

  // Scatters the idle objects and goal of the demonstrated transition in `slot`, already copied
  // into column `column` of `out` (with any hindsight goal). A new place is drawn up to a few times
  // until it is clear; where none is, that object or goal stays.
  void apply(long long slot, int column, Rng& rng, ReplayBatch& out) const;

  // Bit k: object k is idle in `slot`'s transition; kGoalBit: the goal is.
  std::uint8_t idle(long long slot) const { return idle_[static_cast<std::size_t>(slot)]; }
  static constexpr std::uint8_t kGoalBit = 0x80;
  int objects() const { return static_cast<int>(objects_.size()); }

private:
  struct Object {
    int position = 0;       // row of its x in the observation
    int from_effector = -1; // row of (object - effector)'s x; -1: none
    int goal_point = -1;    // its point of achieved_goal; -1: none
  };
  bool clear_of_objects(const Eigen::Vector2f& at, int self, const ReplayBatch& out, int column) const;
  bool scatter_goal(const std::vector<bool>& tied, int column, Rng& rng, ReplayBatch& out) const;
  bool scatter_object(int k, const std::vector<bool>& tied, int column, Rng& rng, ReplayBatch& out) const;

  GoalLayout goal_;
  bool goal_scatter_ = false;
  int effector_ = 0;  // row of the effector's x
  std::vector<Object> objects_;
  std::vector<std::uint8_t> idle_;                 // per slot
  Eigen::Vector2f object_low_, object_high_;       // m: where the demonstrations' objects started (x, y)
  Eigen::Vector2f goal_low_, goal_high_;           // m: where their first desired points were (x, y)
};

}  // namespace rdsim
