#pragma once
#include <cstdint>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rdsim/algorithms/a2c.hpp"
#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/ars.hpp"
#include "rdsim/algorithms/cma_es.hpp"
#include "rdsim/algorithms/bc.hpp"
#include "rdsim/algorithms/demonstrations.hpp"
#include "rdsim/algorithms/dqn.hpp"
#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/ppo.hpp"
#include "rdsim/algorithms/random.hpp"
#include "rdsim/algorithms/sac.hpp"
#include "rdsim/algorithms/td3.hpp"
#include "rdsim/algorithms/trpo.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/memory_estimate.hpp"

// What a training config says about the learner: which algorithm, its networks, and its own
// hyperparameters (the object named after it: "ppo": {...}). Adding an algorithm: its config
// struct with describe() and its factory in its own header, one alternative in
// AlgorithmParams and one row in algorithm_config.cpp's table.
namespace rdsim {

using AlgorithmParams = std::variant<PpoConfig, A2cConfig, DqnConfig, SacConfig, Td3Config, DdpgConfig, TrpoConfig,
                                     ArsConfig, CmaEsConfig, RandomConfig, BcConfig>;

struct AlgorithmConfig {
  NetworkConfig network;
  AlgorithmParams params;  // the chosen algorithm's hyperparameters (PPO by default)
  std::optional<DemonstrationsConfig> demonstrations;  // "demonstrations": learning from a demo file
  std::optional<HerConfig> her;  // "her": hindsight experience replay (sac, td3, ddpg, dqn on goal envs)
  bool normalize_observations = false;  // "normalize_observations" (observation_normalizer.hpp)
  std::string source;      // the config file, for messages

  std::string name() const;  // "ppo", "a2c", "dqn", "sac", ..., "bc"
};

// Whether `algorithm` is one of the off-policy actor-critics over OffPolicy (sac, td3, ddpg).
bool is_off_policy_actor_critic(const std::string& algorithm);
// Whether `algorithm` can take a "her" object: the off-policy methods (those and dqn).
bool takes_her(const std::string& algorithm);
// Whether `algorithm` can take "normalize_observations" (the gradient methods; ARS and CMA-ES
// have their own key).
bool takes_observation_normalization(const std::string& algorithm);

// Every algorithm name, in registry order.
std::vector<std::string> algorithm_names();

// The algorithm's default hyperparameters; rdsim::Error listing the names for an unknown one.
AlgorithmParams default_algorithm_params(const std::string& name);

// Reads "algorithm", "network", the chosen algorithm's object, "demonstrations" and "her" from the top
// level of a training config (`reader`, which keeps checking the other keys). The object of another
// algorithm is an error: it would have no effect; so are demonstrations keys the chosen algorithm
// does not use, and bc without demonstrations.
AlgorithmConfig read_algorithm_config(ConfigReader& reader);

// Writes the same keys, every value resolved, into `out` (a JSON object).
void write_algorithm_config(const AlgorithmConfig& config, nlohmann::json& out);

// Adds what the algorithm of `config` will allocate for `num_envs` envs of `spec` to `estimate`
// (networks with gradients and optimiser state, rollout or replay storage, training activations,
// checkpoint buffers), computed from the config alone (algorithms/memory_estimate.cpp). Throws
// rdsim::Error naming `config.source` when the network does not fit the observations (a CNN too
// deep for the image), as building it would. Adding an algorithm: add its case there.
void estimate_algorithm_memory(const AlgorithmConfig& config, const Spec& spec, int num_envs, MemoryEstimate& estimate);

// rdsim::Error naming `config.source` when no algorithm of rdsim trains on `spec`'s observations
// (camera images with a goal vector beside them); make_algorithm and the memory estimate check it.
void check_trainable(const AlgorithmConfig& config, const Spec& spec);

// Creates the algorithm for envs described by `spec`, with fresh weights drawn from
// Rng::derive(seed, rng_stream::network_init). rdsim::Error when the algorithm cannot handle the
// spec (e.g. DQN with a Box action space, SAC with a Discrete one).
std::unique_ptr<Algorithm> make_algorithm(const AlgorithmConfig& config, std::uint64_t seed, const Spec& spec);

}  // namespace rdsim
