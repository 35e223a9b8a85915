#include "rdsim/algorithms/algorithm.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {

std::vector<Metrics> Algorithm::learn_from_demonstrations(const DemoFile&, const DemonstrationsConfig&, Rng&, bool) {
  throw Error("algorithm \"" + name() + "\" cannot learn from demonstrations (bc, ppo, a2c, dqn, sac, td3 and ddpg can)");
}

}  // namespace rdsim
