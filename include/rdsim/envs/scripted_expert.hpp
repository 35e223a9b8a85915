#pragma once
#include <memory>

#include "rdsim/core/env.hpp"

// A scripted expert: a planner that reads an env's privileged state and emits the env's own actions
// (`rdsim demos record --expert`). The reaching envs have ReachExpert (envs/reach_expert.hpp), the
// manipulation tasks ManipulationExpert (envs/manipulation/manipulation_expert.hpp).
namespace rdsim {

class ScriptedExpert {
public:
  virtual ~ScriptedExpert() = default;
  virtual void reset() = 0;   // call after each env reset
  virtual Action act() = 0;   // the action for the env's current state
};

// The expert of `env` (which must outlive it); rdsim::Error naming the env when it has none.
std::unique_ptr<ScriptedExpert> make_expert(Env& env);

}  // namespace rdsim
