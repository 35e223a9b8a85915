#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm_config.hpp"

// What the algorithm tests vary, in one struct: the algorithm, its own hyperparameters, the
// network and the seed (a training config without env and run settings).
struct Setup {
  std::string algorithm = "ppo";
  std::uint64_t seed = 0;
  std::string source;                // config file named in messages
  long long total_timesteps = 0;     // the tests' training budget
  rdsim::NetworkConfig network;
  rdsim::PpoConfig ppo;
  rdsim::A2cConfig a2c;
  rdsim::DqnConfig dqn;
};

inline std::unique_ptr<rdsim::Algorithm> make_algorithm(const Setup& s, const rdsim::Spec& spec) {
  rdsim::AlgorithmConfig c;
  c.network = s.network;
  c.source = s.source;
  if (s.algorithm == "ppo") c.params = s.ppo;
  if (s.algorithm == "a2c") c.params = s.a2c;
  if (s.algorithm == "dqn") c.params = s.dqn;
  return rdsim::make_algorithm(c, s.seed, spec);
}
