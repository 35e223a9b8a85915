#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/off_policy_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Twin delayed deep deterministic policy gradient (algorithms/td3.cpp) for Box action spaces,
// and DDPG as TD3 with its three additions switched off.
namespace rdsim {

// The "td3" object of a training config. Defaults: Stable-Baselines3's TD3.
struct Td3Config : OffPolicyConfig {
  bool twin_q = true;                // clipped double Q-learning (two critics)
  int policy_delay = 2;              // critic updates per actor (and target) update
  double target_policy_noise = 0.2;  // target policy smoothing: std of the noise on a'
  double target_noise_clip = 0.5;
  std::string action_noise = "normal";  // exploration: "normal", "ornstein_uhlenbeck" or "none"
  double action_noise_std = 0.1;        // in units of half the action range
  double ou_theta = 0.15;
  double ou_dt = 0.01;
};

// The "ddpg" object: the same keys; the defaults switch TD3's additions off (one critic, actor
// updated every step, no target smoothing), as Stable-Baselines3's DDPG.
struct DdpgConfig : Td3Config {
  DdpgConfig() {
    twin_q = false;
    policy_delay = 1;
    target_policy_noise = 0.0;
  }
};

template <class V, class C>
  requires config::Describes<C, Td3Config>
void describe(V& v, C& c) {
  describe_off_policy(v, c, "Adam step size of actor and critics", "Polyak factor of the target networks per actor update");
  v.field("twin_q", c.twin_q, "two critics, targets from their minimum (false: one critic, DDPG)");
  v.field("policy_delay", c.policy_delay, config::Range{1, 1'000'000},
          "critic updates per actor and target update (1: every step, DDPG)");
  v.field("target_policy_noise", c.target_policy_noise, config::Range{0.0, 10.0},
          "std of the Gaussian noise added to target actions (0: no smoothing, DDPG)");
  v.field("target_noise_clip", c.target_noise_clip, config::Range{0.0, 10.0}, "that noise is clipped to +-this");
  v.choice("action_noise", c.action_noise, {"normal", "ornstein_uhlenbeck", "none"}, "exploration noise process");
  v.field("action_noise_std", c.action_noise_std, config::Range{0.0, 10.0},
          "std (sigma) of the exploration noise, in units of half the action range");
  v.field("ou_theta", c.ou_theta, config::Range{0.0, 1e3}, "Ornstein-Uhlenbeck mean reversion rate");
  v.field("ou_dt", c.ou_dt, config::Range{1e-6, 1e3}, "Ornstein-Uhlenbeck time step");
  v.check(c.batch_size <= c.buffer_size, "batch_size", "expected at most buffer_size (" + std::to_string(c.buffer_size) + ")");
}

template <class V, class C>
  requires config::Describes<C, DdpgConfig>
void describe(V& v, C& c) {
  using Base = std::conditional_t<std::is_const_v<C>, const Td3Config, Td3Config>;
  describe(v, static_cast<Base&>(c));
}

// rdsim::Error naming `where` (the config file) when the env has discrete actions, pixels,
// unbounded actions, or the replay buffer would not fit in memory; with `her` (hindsight experience
// replay), when the env is not goal-conditioned.
std::unique_ptr<Algorithm> make_td3(const Td3Config& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where, const std::optional<HerConfig>& her);
// The same algorithm under the name "ddpg".
std::unique_ptr<Algorithm> make_ddpg(const DdpgConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                     const Spec& spec, const std::string& where, const std::optional<HerConfig>& her);

}  // namespace rdsim
