#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Behaviour cloning (algorithms/bc.cpp): the policy is fitted to a demonstration file before the
// first update (the config's "demonstrations" object, which bc requires: demonstrations.hpp);
// then every update only runs the cloned policy in the envs, so progress.csv and episodes.csv show
// how well it does. The model file holds an ActorCritic like PPO's (its critic untrained), so
// `rdsim replay` runs it.
namespace rdsim {

// The "bc" object of a training config.
struct BcConfig {
  int n_steps = 256;
  bool deterministic = true;
};

template <class V, class C>
  requires config::Describes<C, BcConfig>
void describe(V& v, C& c) {
  v.field("n_steps", c.n_steps, config::Range{1, 1'000'000}, "env steps per env per update of running the cloned policy");
  v.field("deterministic", c.deterministic, "run the most likely action (as `rdsim replay`), else sample");
}

std::unique_ptr<Algorithm> make_bc(const BcConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                   const Spec& spec, const std::string& where);

}  // namespace rdsim
