#include "rdsim/algorithms/algorithm.hpp"

#include "rdsim/policy/policy_program.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

std::vector<Metrics> Algorithm::learn_from_demonstrations(const DemoFile&, const DemonstrationsConfig&, Rng&, bool) {
  throw Error("algorithm \"" + name() + "\" cannot learn from demonstrations (bc, ppo, a2c, dqn, sac, td3 and ddpg can)");
}

PolicyProgram Algorithm::policy_program() const {
  throw Error("algorithm \"" + name() + "\": it has no policy to export (every other algorithm "
              "has)");
}

void Algorithm::enable_observation_normalization() {
  throw Error("algorithm \"" + name() + "\" cannot normalize observations (ppo, a2c, trpo, dqn, sac, td3 and ddpg can)");
}

}  // namespace rdsim
