#pragma once
#include <memory>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/env.hpp"

// Domain randomization of a robot env ("randomize": {...} in its config): what a real robot's
// sensors and controller add to the simulation, so that a policy does not rely on exact, instant
// values. Drawn from the env's own stream (seeded by its reset seed: the same seed gives the same
// noise), kept in its saved state (a resumed run continues bit-identically), and applied around
// any robot env, local or remote (the server's env applies it). Today: Gaussian observation noise
// and action latency; physical parameters, placements and cameras are not randomized yet.
namespace rdsim {

struct Randomization {
  double observation_noise = 0.0;  // standard deviation, in the observed values' own units
  int action_latency = 0;          // env steps

  bool active() const { return observation_noise > 0.0 || action_latency > 0; }
};

template <class V, class C>
  requires config::Describes<C, Randomization>
void describe(V& v, C& c) {
  v.field("observation_noise", c.observation_noise, config::Range{0.0, 1000.0},
          "standard deviation of Gaussian noise added to each observed value at every reset and step, in the "
          "values' own units (metres for positions, so 0.005 is 5 mm); a goal env's desired goal stays exact; "
          "ground-truth observations only; 0 = none");
  v.field("action_latency", c.action_latency, config::Range{0, 100000},
          "env steps between an action and the step that executes it (each step runs the action given that "
          "many steps before; the first steps of an episode run its first action); shorter than max_steps; 0 = none");
}

// The option group robot envs list (their defaults hold it inactive).
struct RandomizeOptions {
  Randomization randomize;
};

template <class V, class C>
  requires config::Describes<C, RandomizeOptions>
void describe(V& v, C& c) {
  v.object("randomize", c.randomize, "domain randomization, drawn from the env's seeded stream (docs: Environments)");
}

// `env` with `r` applied around it (make_env does this), or `env` itself when r is inactive. The
// config rules (latency shorter than max_steps, noise on ground-truth observations) are
// read_env_config's (envs/registry.cpp).
std::unique_ptr<Env> randomized(std::unique_ptr<Env> env, const Randomization& r);

}  // namespace rdsim
