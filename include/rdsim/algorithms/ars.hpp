#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Augmented random search (algorithms/ars.cpp).
namespace rdsim {

// The "ars" object of a training config. Defaults: Stable-Baselines3-contrib's ARS; the policy
// is network.hidden_sizes ([] = linear, the paper's) on standardised observations.
struct ArsConfig {
  int n_delta = 8;
  int n_top = 0;
  double learning_rate = 0.02;
  double delta_std = 0.05;
  bool zero_init = true;
  bool normalize_observations = true;
  int episodes_per_candidate = 1;
};

template <class V, class C>
  requires config::Describes<C, ArsConfig>
void describe(V& v, C& c) {
  v.field("n_delta", c.n_delta, config::Range{1, 100'000}, "random directions per update (2 x n_delta candidates)");
  v.field("n_top", c.n_top, config::Range{0, 100'000}, "best directions used in the step; 0 = all n_delta");
  v.check(c.n_top <= c.n_delta, "n_top", "expected at most n_delta (" + std::to_string(c.n_delta) + ")");
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1e3}, "step size alpha");
  v.field("delta_std", c.delta_std, config::Range{1e-9, 1e3}, "exploration noise nu: candidates are theta +- nu delta");
  v.field("zero_init", c.zero_init, "start from all-zero parameters (the paper's), else the network's random init");
  v.field("normalize_observations", c.normalize_observations,
          "standardise observations by their running mean and std (ARS V2)");
  v.field("episodes_per_candidate", c.episodes_per_candidate, config::Range{1, 10'000},
          "episodes averaged into each candidate's return");
}

// rdsim::Error naming `where` (the config file) for pixel observations.
std::unique_ptr<Algorithm> make_ars(const ArsConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where);

}  // namespace rdsim
