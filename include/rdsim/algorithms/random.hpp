#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// The random agent (algorithms/random.cpp): uniform actions, the baseline row of every
// comparison (RobotDrlSim's random_agent). It learns nothing and has no weights.
namespace rdsim {

// The "random" object of a training config.
struct RandomConfig {
  int n_steps = 1000;
};

template <class V, class C>
  requires config::Describes<C, RandomConfig>
void describe(V& v, C& c) {
  v.field("n_steps", c.n_steps, config::Range{1, 1'000'000}, "env steps per env per update (one progress.csv row)");
}

std::unique_ptr<Algorithm> make_random(const RandomConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                       const Spec& spec, const std::string& where);

}  // namespace rdsim
