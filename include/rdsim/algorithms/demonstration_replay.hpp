#pragma once
#include <functional>
#include <optional>
#include <vector>

#include "rdsim/algorithms/demonstration_scatter.hpp"
#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/hindsight_replay.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// Demonstrated transitions for the off-policy methods (SAC, TD3/DDPG; Vecerik et al. 2017,
// Nair et al. 2018 "Overcoming exploration with demonstrations"): every demonstrated step in a
// buffer of its own that is never overwritten, from which each minibatch draws a fixed share, with
// hindsight goals too when the run uses HER (each demonstrated episode is one stream of its own).
//
// Planar shift (demonstrations.shift > 0): a goal env's physics and its Cartesian actions (dx, dy,
// dz, fingers) do not depend on where on the table a scene lies, so a demonstrated transition moved
// as a whole by (dx, dy) is one the expert could have shown for the scene moved so: every world
// position of both observations (the effector's, each object's, the achieved and desired goals)
// moves by the same offset; velocities, orientations, relative positions, the finger opening, the
// action and the reward (a distance between goals, both moved) stay. Each drawn transition gets its
// own offset, uniform in [-shift, shift] m on x and on y, after any hindsight relabelling. It is an
// approximation near the workspace's edges and the arm's reach, where the real env clips.
//
// Scatter (demonstrations.scatter > 0; demonstration_scatter.hpp): that share of the drawn
// transitions get new places for the objects (and with scatter_goal the goal) the demonstrated step
// does not depend on, after any hindsight relabelling and before the shift.
namespace rdsim {

struct DemoFile;  // demos/demo_file.hpp

// The rows of `spec`'s observation that hold the x of a 3-D world position (its y is the next row):
// a goal env's parts named "..._position" of 3 values, and every point of achieved_goal and
// desired_goal. Empty where a shift is not defined: an env without goals or names, or one whose
// observation holds joint positions (actions per joint, which a shift would not carry over).
std::vector<int> planar_position_rows(const Spec& spec);

class DemonstrationReplay {
public:
  // Box actions are stored as the algorithm acts: `normalize` maps an env action to the
  // networks' [-1, 1]. `shift` (m; > 0 needs planar_position_rows(spec)) and `scatter` (a share;
  // > 0 needs DemonstrationScatter::supported(spec)) are checked by the caller.
  // Throws rdsim::Error naming the file when it holds no step.
  DemonstrationReplay(const DemoFile& demos, const Spec& spec, const std::optional<HerConfig>& her,
                      const std::function<Eigen::VectorXf(const Action&)>& normalize, double shift = 0.0,
                      double scatter = 0.0, bool scatter_goal = false);

  long long transitions() const { return buffer_.size(); }
  const ReplayBuffer& buffer() const { return buffer_; }

  // `count` transitions into columns [first, first + count) of `out` (shaped by the caller), each
  // scattered (that share) and shifted when asked (the draws from `rng` after the transitions).
  void sample_into(int first, int count, Rng& rng, ReplayBatch& out) const;

private:
  void shift_into(int first, int count, Rng& rng, ReplayBatch& out) const;

  ReplayBuffer buffer_;
  std::optional<HindsightReplay> her_;
  float shift_ = 0.0f;            // m
  std::vector<int> shift_rows_;   // planar_position_rows when shift_ > 0
  double scatter_ = 0.0;          // share of the drawn transitions scattered
  std::optional<DemonstrationScatter> scatter_by_;  // when scatter_ > 0
};

}  // namespace rdsim
