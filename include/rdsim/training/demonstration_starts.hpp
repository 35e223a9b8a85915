#pragma once
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/demos/demo_file.hpp"

// Episodes that start from states of the demonstrations (Nair et al. 2018, "Overcoming exploration
// in reinforcement learning with demonstrations": resets to demonstration states). With
// demonstrations.start_fraction p, each reset of a training env starts, with probability p, where a
// demonstrator had got to: a demonstrated episode and a step along it are drawn uniformly, the env
// is reset with that episode's seed and the demonstrated actions run up to that step. The episode
// then goes on from there under the agent's control, for what is left of the env's step limit.
// With demonstrations.start_redraw q, that share of those starts then draws again what the
// demonstrator has not moved yet (SceneRedraw: in a manipulation task the cubes still where the
// reset put them, and the goal unless a cube is on it): the arm and what it has done stay, the
// layout is new, so that the starts do not all come from the demonstrations' few layouts.
// Long tasks (stack: two cubes) thereby see their later stages from the start of training instead of
// only after the agent has learnt the earlier ones.
//
// The replayed steps are part of the reset: they are no timesteps, no transitions and no episode of
// episodes.csv's; the episodes that start from a demonstration are counted there as any other (an
// "eval" object measures the policy from the env's own starts). Other resets run the env with a
// seed drawn from the wrapper's stream. Everything is drawn from a stream derived from the env's
// reset seed (rng_stream::demonstration_starts) and saved with the env's state, so runs stay the same
// on any thread count and after --resume.
namespace rdsim {

// `env` with `fraction` (in (0, 1]) of its resets starting from `demos`' states, `redraw` (in [0, 1])
// of those with a new layout. `where` names the key in errors. rdsim::Error when no episode of
// `demos` has a reset seed (a person's episodes recorded after a continued reset carry none) or when
// a replay does not reproduce the recorded observations (a file recorded by another build of rdsim,
// or with other env options). A `redraw` above 0 needs an env that is a SceneRedraw
// (training/env_source.cpp says so to the user).
std::unique_ptr<Env> start_from_demonstrations(std::unique_ptr<Env> env, std::shared_ptr<const DemoFile> demos,
                                               double fraction, const std::string& where, double redraw = 0.0);

}  // namespace rdsim
