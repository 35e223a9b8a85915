#pragma once
// What an algorithm will allocate, from its config alone (estimate_algorithm_memory in
// algorithm_config.hpp): the shared building blocks (memory_footprint.cpp) and each algorithm's
// estimate, defined beside the algorithm in algorithms/<name>.cpp. Private to the algorithms library.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/memory_estimate.hpp"
#include "rdsim/nn/cnn.hpp"
#include "rdsim/vecenv/observation_batch.hpp"

namespace rdsim::memory {

constexpr double kFloat = 4.0;

// Parameters of a network and the activations one sample keeps in a training pass (floats).
struct Footprint {
  double params = 0.0;
  double activations = 0.0;
  Footprint& operator+=(const Footprint& o) {
    params += o.params;
    activations += o.activations;
    return *this;
  }
};

Footprint mlp(double in, const std::vector<int>& hidden, double out);
// Convs then the dense head; the same shape checks as building it (an image too small for the
// kernels is named here, before anything is allocated).
Footprint cnn(const nn::CnnShape& shape, const std::string& where);
Footprint actor_critic(const NetworkConfig& n, const Spec& spec, const std::string& where);
Footprint q_network(const NetworkConfig& n, const Spec& spec, const std::string& where);
// "network.cnn" or "network.hidden_sizes": the keys that size the networks.
const char* network_keys(const Spec& spec);

// PPO, A2C, TRPO, BC: one actor-critic, Adam/RMSprop state, a rollout of n_steps x num_envs
// samples, training passes over `batch` samples.
void on_policy(const NetworkConfig& n, const Spec& spec, int num_envs, int n_steps, double batch, const char* algo,
               const std::string& where, MemoryEstimate& e);
// SAC, TD3, DDPG: an actor (policy_out outputs), two critics on (observation, action), their
// target copies, Adam state, a replay buffer of Box actions, training passes over batch_size samples.
void actor_critics(const NetworkConfig& n, const Spec& spec, int num_envs, long long buffer_size, int batch_size,
                   double policy_out, bool target_actor, const char* algo, MemoryEstimate& e);
// ARS, CMA-ES: one flat policy, `copies` parameter vectors (perturbations, candidates) and, for
// CMA-ES, the covariance and its eigenvectors (doubles, parameters squared).
void policy_search(const NetworkConfig& n, const Spec& spec, int num_envs, double copies, bool covariance,
                   const char* keys, MemoryEstimate& e);

}  // namespace rdsim::memory

namespace rdsim {

// Each algorithm's estimate: `c` is the whole algorithm config (network, source, demonstrations).
void estimate_memory(const PpoConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const A2cConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const BcConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const DqnConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const SacConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const Td3Config& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const DdpgConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const TrpoConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const ArsConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const CmaEsConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);
void estimate_memory(const RandomConfig& p, const AlgorithmConfig& c, const Spec& spec, int num_envs, MemoryEstimate& e);

}  // namespace rdsim
