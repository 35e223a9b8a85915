#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Proximal Policy Optimisation with the clipped surrogate objective (algorithms/ppo.cpp).
namespace rdsim {

// The "ppo" object of a training config. Defaults: Stable-Baselines3's.
struct PpoConfig {
  int n_steps = 2048;
  int batch_size = 64;
  int n_epochs = 10;
  double learning_rate = 3e-4;
  bool anneal_lr = false;
  double adam_eps = 1e-5;
  double gamma = 0.99;
  double gae_lambda = 0.95;
  double clip_range = 0.2;
  bool anneal_clip_range = false;
  double clip_range_vf = 0.0;
  double ent_coef = 0.0;
  double vf_coef = 0.5;
  double max_grad_norm = 0.5;
  bool normalize_advantage = true;
  double target_kl = 0.0;
};

template <class V, class C>
  requires config::Describes<C, PpoConfig>
void describe(V& v, C& c) {
  v.field("n_steps", c.n_steps, config::Range{1, 1'000'000}, "env steps per env per update (rollout length)");
  v.field("batch_size", c.batch_size, config::Range{1, 100'000'000}, "minibatch size in samples");
  v.field("n_epochs", c.n_epochs, config::Range{1, 10'000}, "passes over each rollout");
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1.0}, "Adam step size");
  v.field("anneal_lr", c.anneal_lr, "learning rate decays linearly to 0 over total_timesteps");
  v.field("adam_eps", c.adam_eps, config::Range{0.0, 1.0}, "Adam epsilon");
  v.field("gamma", c.gamma, config::Range{0.0, 1.0}, "discount factor");
  v.field("gae_lambda", c.gae_lambda, config::Range{0.0, 1.0}, "GAE lambda");
  v.field("clip_range", c.clip_range, config::Range{0.0, 10.0}, "policy ratio clip");
  v.field("anneal_clip_range", c.anneal_clip_range, "clip_range decays linearly to 0 over total_timesteps");
  v.field("clip_range_vf", c.clip_range_vf, config::Range{0.0, 1e9},
          "value clip around the rollout's value; 0 = no value clipping");
  v.field("ent_coef", c.ent_coef, config::Range{0.0, 100.0}, "entropy bonus weight");
  v.field("vf_coef", c.vf_coef, config::Range{0.0, 100.0}, "value loss weight");
  v.field("max_grad_norm", c.max_grad_norm, config::Range{1e-9, 1e9}, "global gradient-norm clip");
  v.field("normalize_advantage", c.normalize_advantage, "advantages standardised per minibatch");
  v.field("target_kl", c.target_kl, config::Range{0.0, 100.0},
          "stop an update's epochs once the approximate KL exceeds 1.5 x this; 0 = never");
}

// `where` (the config file) prefixes messages about the network.
std::unique_ptr<Algorithm> make_ppo(const PpoConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where);

}  // namespace rdsim
