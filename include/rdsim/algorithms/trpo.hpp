#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Trust region policy optimisation (algorithms/trpo.cpp).
namespace rdsim {

// The "trpo" object of a training config. Defaults: Stable-Baselines3-contrib's.
struct TrpoConfig {
  int n_steps = 2048;
  int batch_size = 128;
  double learning_rate = 1e-3;
  double gamma = 0.99;
  double gae_lambda = 0.95;
  int cg_max_steps = 15;
  double cg_damping = 0.1;
  double line_search_shrinking_factor = 0.8;
  int line_search_max_iter = 10;
  int n_critic_updates = 10;
  double target_kl = 0.01;
  bool normalize_advantage = true;
};

template <class V, class C>
  requires config::Describes<C, TrpoConfig>
void describe(V& v, C& c) {
  v.field("n_steps", c.n_steps, config::Range{1, 1'000'000}, "env steps per env per update (rollout length)");
  v.field("batch_size", c.batch_size, config::Range{1, 100'000'000}, "minibatch size of the critic's updates");
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1.0}, "Adam step size of the critic");
  v.field("gamma", c.gamma, config::Range{0.0, 1.0}, "discount factor");
  v.field("gae_lambda", c.gae_lambda, config::Range{0.0, 1.0}, "GAE lambda");
  v.field("cg_max_steps", c.cg_max_steps, config::Range{1, 10'000}, "conjugate-gradient iterations per update");
  v.field("cg_damping", c.cg_damping, config::Range{0.0, 1e3}, "added to the Fisher matrix's diagonal (F + damping I)");
  v.field("line_search_shrinking_factor", c.line_search_shrinking_factor, config::Range{0.01, 0.99},
          "the step shrinks by this factor per rejected line-search try");
  v.field("line_search_max_iter", c.line_search_max_iter, config::Range{1, 1'000}, "line-search tries");
  v.field("n_critic_updates", c.n_critic_updates, config::Range{0, 10'000}, "critic epochs over each rollout");
  v.field("target_kl", c.target_kl, config::Range{1e-9, 10.0},
          "trust region: largest mean KL(old || new) of an accepted policy step");
  v.field("normalize_advantage", c.normalize_advantage, "advantages standardised per rollout");
}

// rdsim::Error naming `where` (the config file) for network.shared or pixel observations (TRPO
// needs a policy network of its own).
std::unique_ptr<Algorithm> make_trpo(const TrpoConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                     const Spec& spec, const std::string& where);

}  // namespace rdsim

namespace rdsim::trpo {

// Solves A x = b for a symmetric positive definite A given as a product function, by at most
// `max_steps` conjugate-gradient iterations from x = 0, stopping early once the squared
// residual is below `residual_tol`.
Eigen::VectorXf conjugate_gradient(const std::function<Eigen::VectorXf(const Eigen::VectorXf&)>& product,
                                   const Eigen::VectorXf& b, int max_steps, float residual_tol = 1e-10f);

}  // namespace rdsim::trpo
