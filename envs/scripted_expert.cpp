#include "rdsim/envs/scripted_expert.hpp"

#include "rdsim/core/error.hpp"
#include "rdsim/envs/manipulation/manipulation_expert.hpp"
#include "rdsim/envs/reaching/reach_expert.hpp"

namespace rdsim {

std::unique_ptr<ScriptedExpert> make_expert(Env& env) {
  if (dynamic_cast<ManipulationEnv*>(&env)) return std::make_unique<ManipulationExpert>(env);
  if (dynamic_cast<ReachEnv*>(&env)) return std::make_unique<ReachExpert>(env);
  throw Error("env " + env.spec().env_name + " has no scripted expert (the reaching and manipulation tasks have one)");
}

}  // namespace rdsim
