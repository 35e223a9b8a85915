#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Synchronous advantage actor-critic (algorithms/a2c.cpp).
namespace rdsim {

// The "a2c" object of a training config. Defaults: Stable-Baselines3's (RMSprop like baselines).
struct A2cConfig {
  int n_steps = 5;
  double learning_rate = 7e-4;
  bool anneal_lr = false;
  std::string optimizer = "rmsprop";
  double rms_alpha = 0.99;
  double rms_eps = 1e-5;
  bool rms_tf_style = false;
  double gamma = 0.99;
  double gae_lambda = 1.0;
  double ent_coef = 0.0;
  double vf_coef = 0.5;
  double max_grad_norm = 0.5;
  bool normalize_advantage = false;
};

template <class V, class C>
  requires config::Describes<C, A2cConfig>
void describe(V& v, C& c) {
  v.field("n_steps", c.n_steps, config::Range{1, 1'000'000}, "env steps per env per update");
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1.0}, "optimiser step size");
  v.field("anneal_lr", c.anneal_lr, "learning rate decays linearly to 0 over total_timesteps");
  v.choice("optimizer", c.optimizer, {"rmsprop", "adam"}, "update rule");
  v.field("rms_alpha", c.rms_alpha, config::Range{0.0, 1.0}, "RMSprop square-average decay");
  v.field("rms_eps", c.rms_eps, config::Range{0.0, 1.0}, "RMSprop (and Adam) epsilon");
  v.field("rms_tf_style", c.rms_tf_style, "RMSprop as TensorFlow: eps inside the sqrt, square average starting at 1");
  v.field("gamma", c.gamma, config::Range{0.0, 1.0}, "discount factor");
  v.field("gae_lambda", c.gae_lambda, config::Range{0.0, 1.0}, "GAE lambda; 1 = plain n-step returns");
  v.field("ent_coef", c.ent_coef, config::Range{0.0, 100.0}, "entropy bonus weight");
  v.field("vf_coef", c.vf_coef, config::Range{0.0, 100.0}, "value loss weight");
  v.field("max_grad_norm", c.max_grad_norm, config::Range{1e-9, 1e9}, "global gradient-norm clip");
  v.field("normalize_advantage", c.normalize_advantage, "advantages standardised per update");
  v.check(c.optimizer == "rmsprop" || (c.rms_alpha == A2cConfig{}.rms_alpha && !c.rms_tf_style),
          c.rms_tf_style ? "rms_tf_style" : "rms_alpha", "has no effect with optimizer \"adam\" (RMSprop only)");
}

// `where` (the config file) prefixes messages about the network.
std::unique_ptr<Algorithm> make_a2c(const A2cConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where);

}  // namespace rdsim
