#pragma once
#include <string>

#include "rdsim/core/env_caches.hpp"

// Optional capability of an Env (implemented next to rdsim::Env by envs that can do it): its
// complete state (physics, step counter, random generator) as bytes, so that a training run
// resumed from a checkpoint continues bit-identically to one that was never interrupted.
//
// What "complete" means for a physics engine: Bullet keeps caches between steps that are not part
// of the simulated state and cannot be saved (env_caches.hpp). They are instead brought to one
// canonical state, the same on both paths: training calls drop_caches() on every env at every
// update boundary, whether it writes a checkpoint there or not, and load_state() leaves the env as
// drop_caches() does. An env without such caches keeps the default no-op.
namespace rdsim {

class EnvState : public EnvCaches {
public:
  virtual ~EnvState() = default;
  virtual std::string save_state() const = 0;
  // Throws rdsim::Error naming `source` when the bytes are not a state of this env. On return the
  // env is in the state save_state() recorded, with its caches dropped.
  virtual void load_state(const std::string& bytes, const std::string& source) = 0;
  // Clears what save_state() does not record (see above).
  void drop_caches() override {}
};

}  // namespace rdsim
