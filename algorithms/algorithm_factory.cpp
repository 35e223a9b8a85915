#include "rdsim/algorithm.hpp"
#include "rdsim/error.hpp"
#include "rdsim/train_config.hpp"

namespace rdsim {

std::unique_ptr<Algorithm> make_algorithm(const TrainConfig& config, const Spec& spec) {
  if (config.algorithm == "ppo") return make_ppo(config, spec);
  if (config.algorithm == "a2c") return make_a2c(config, spec);
  if (config.algorithm == "dqn") return make_dqn(config, spec);
  throw Error(config.source + ": algorithm: unknown algorithm \"" + config.algorithm + "\"");
}

}  // namespace rdsim
