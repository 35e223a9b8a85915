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
  rdsim::SacConfig sac;
  rdsim::Td3Config td3;
  rdsim::DdpgConfig ddpg;
  rdsim::TrpoConfig trpo;
  rdsim::ArsConfig ars;
  rdsim::CmaEsConfig cma_es;
  rdsim::RandomConfig random;
  rdsim::BcConfig bc;
};

// The algorithm config a training config with these values would hold.
inline rdsim::AlgorithmConfig algorithm_config(const Setup& s) {
  rdsim::AlgorithmConfig c;
  c.network = s.network;
  c.source = s.source;
  c.params = rdsim::default_algorithm_params(s.algorithm);
  std::visit(
      [&](auto& p) {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, rdsim::PpoConfig>) p = s.ppo;
        if constexpr (std::is_same_v<P, rdsim::A2cConfig>) p = s.a2c;
        if constexpr (std::is_same_v<P, rdsim::DqnConfig>) p = s.dqn;
        if constexpr (std::is_same_v<P, rdsim::SacConfig>) p = s.sac;
        if constexpr (std::is_same_v<P, rdsim::Td3Config>) p = s.td3;
        if constexpr (std::is_same_v<P, rdsim::DdpgConfig>) p = s.ddpg;
        if constexpr (std::is_same_v<P, rdsim::TrpoConfig>) p = s.trpo;
        if constexpr (std::is_same_v<P, rdsim::ArsConfig>) p = s.ars;
        if constexpr (std::is_same_v<P, rdsim::CmaEsConfig>) p = s.cma_es;
        if constexpr (std::is_same_v<P, rdsim::RandomConfig>) p = s.random;
        if constexpr (std::is_same_v<P, rdsim::BcConfig>) p = s.bc;
      },
      c.params);
  return c;
}

inline std::unique_ptr<rdsim::Algorithm> make_algorithm(const Setup& s, const rdsim::Spec& spec) {
  return rdsim::make_algorithm(algorithm_config(s), s.seed, spec);
}

// Toy-sized hyperparameters for every gradient algorithm (16-16 networks, short rollouts, learning
// after 40 steps): a few hundred toy-env steps exercise every part of an update.
inline Setup small_setup(const std::string& algorithm, std::uint64_t seed) {
  Setup s;
  s.algorithm = algorithm;
  s.seed = seed;
  s.network.hidden_sizes = {16, 16};
  s.ppo.n_steps = 16;
  s.ppo.batch_size = 32;
  s.a2c.n_steps = 8;
  s.trpo.n_steps = 32;
  s.dqn.learning_starts = 40;
  s.dqn.buffer_size = 1000;
  s.dqn.batch_size = 16;
  s.sac.learning_starts = 40;
  s.sac.buffer_size = 1000;
  s.sac.batch_size = 16;
  s.td3.learning_starts = 40;
  s.td3.buffer_size = 1000;
  s.td3.batch_size = 16;
  s.ddpg.learning_starts = 40;
  s.ddpg.buffer_size = 1000;
  s.ddpg.batch_size = 16;
  return s;
}
