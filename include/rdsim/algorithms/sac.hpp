#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/network_config.hpp"
#include "rdsim/algorithms/off_policy_config.hpp"
#include "rdsim/core/config_fields.hpp"

// Soft actor-critic (algorithms/sac.cpp) for Box action spaces.
namespace rdsim {

// The "sac" object of a training config. Defaults: Stable-Baselines3's.
struct SacConfig : OffPolicyConfig {
  SacConfig() { learning_rate = 3e-4; }
  bool auto_entropy = true;
  double ent_coef = 1.0;
  double target_entropy = -1.0;
  int target_update_interval = 1;
};

template <class V, class C>
  requires config::Describes<C, SacConfig>
void describe(V& v, C& c) {
  describe_off_policy(v, c, "Adam step size of actor, critics and entropy coefficient",
                      "Polyak factor of the target critics per update");
  v.field("auto_entropy", c.auto_entropy, "tune the entropy coefficient towards target_entropy (SB3's ent_coef \"auto\")");
  v.field("ent_coef", c.ent_coef, config::Range{1e-8, 1e4},
          "entropy coefficient alpha: its initial value with auto_entropy, else fixed");
  v.field("target_entropy", c.target_entropy, config::Range{-1e3, 1e3},
          "target entropy per action dimension (SB3's \"auto\" is -1, i.e. -dim in total)");
  v.field("target_update_interval", c.target_update_interval, config::Range{1, 1'000'000},
          "gradient steps between target-critic updates");
  v.check(c.batch_size <= c.buffer_size, "batch_size", "expected at most buffer_size (" + std::to_string(c.buffer_size) + ")");
}

// rdsim::Error naming `where` (the config file) when the env has discrete actions, pixels,
// unbounded actions, or the replay buffer would not fit in memory; with `her` (hindsight experience
// replay), when the env is not goal-conditioned.
std::unique_ptr<Algorithm> make_sac(const SacConfig& config, const NetworkConfig& network, std::uint64_t seed,
                                    const Spec& spec, const std::string& where, const std::optional<HerConfig>& her);

}  // namespace rdsim

namespace rdsim::sac {

// Bounds of the actor's log standard deviation (SB3's): outputs outside are clamped and
// receive no gradient.
inline constexpr float log_std_min = -20.0f;
inline constexpr float log_std_max = 2.0f;

// Soft TD targets y_j = r_j + gamma (1 - terminated_j) (min_i Q_target_i(s'_j, a'_j) - alpha log pi(a'_j | s'_j)),
// a'_j drawn from the current policy at s'_j. Truncated transitions carry terminated = 0.
Eigen::VectorXf soft_td_targets(const Eigen::VectorXf& rewards, const Eigen::VectorXf& terminated,
                                const Eigen::VectorXf& next_q_min, const Eigen::VectorXf& next_log_probs, float alpha,
                                float gamma);

}  // namespace rdsim::sac
