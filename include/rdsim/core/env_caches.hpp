#pragma once

// Optional capability of an Env: its engine keeps caches between steps that are not part of the
// simulated state but change later steps (Bullet's contact manifolds with their warm-starting
// impulses, the order of its overlapping pairs), and drop_caches() brings them to one canonical
// state. Training calls it on every env at every update boundary (VecEnv::drop_caches), so a run
// gives the same results whether or not it was resumed from a checkpoint (EnvState::load_state
// leaves the caches dropped too) and whether its envs run here or in an `rdsim serve` (RemoteEnv
// forwards the call to the server's env).
namespace rdsim {

class EnvCaches {
public:
  virtual ~EnvCaches() = default;
  // Cheap; changes the simulation only as much as restarting the engine's contact caches does,
  // identically on every path.
  virtual void drop_caches() = 0;
};

}  // namespace rdsim
