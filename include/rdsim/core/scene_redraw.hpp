#pragma once
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// Optional capability of an Env (implemented next to rdsim::Env by envs that can do it): mid-episode,
// draw again what nobody has moved since the reset. Training's demonstration starts use it
// (demonstrations.start_redraw, training/demonstration_starts.hpp): a demonstrated state keeps the
// arm and what the demonstrator has done (a cube in the gripper, a cube on its goal) and gets a new
// layout for the rest, so that a few demonstrations start episodes in as many layouts as the env's
// own resets.
namespace rdsim {

class SceneRedraw {
public:
  virtual ~SceneRedraw() = default;
  // Draws, from `rng` only, new places for what has not moved since the last reset, as the env's
  // reset would, clear of what has moved; the observation afterwards in `out`. Returns whether
  // anything moved. Call it between a reset and the steps that follow, with the episode not ended.
  virtual bool redraw_unmoved(Rng& rng, ObservationOut out) = 0;
};

}  // namespace rdsim
