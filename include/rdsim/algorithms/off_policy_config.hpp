#pragma once
#include "rdsim/core/config_fields.hpp"

// The keys SAC's and TD3's (and DDPG's) config objects share: the replay buffer, the schedule of
// collecting and training (off_policy.hpp) and the learning of the critics.
namespace rdsim {

struct OffPolicyConfig {
  double learning_rate = 1e-3;
  long long buffer_size = 1000000;
  long long learning_starts = 100;
  int batch_size = 256;
  double tau = 0.005;
  double gamma = 0.99;
  int train_freq = 1;
  int gradient_steps = 1;
};

// Describes the shared keys, first in the method's object; each method names what its
// learning rate and tau apply to.
template <class V, class C>
void describe_off_policy(V& v, C& c, const char* learning_rate_help, const char* tau_help) {
  constexpr long long max_steps = 1'000'000'000'000LL;
  v.field("learning_rate", c.learning_rate, config::Range{0.0, 1.0}, learning_rate_help);
  v.field("buffer_size", c.buffer_size, config::Range{1LL, 100'000'000LL}, "replay buffer capacity (transitions)");
  v.field("learning_starts", c.learning_starts, config::Range{0LL, max_steps},
          "env steps of uniform random actions before learning starts");
  v.field("batch_size", c.batch_size, config::Range{1, 1'000'000}, "transitions per gradient step");
  v.field("tau", c.tau, config::Range{0.0, 1.0}, tau_help);
  v.field("gamma", c.gamma, config::Range{0.0, 1.0}, "discount factor");
  v.field("train_freq", c.train_freq, config::Range{1, 1'000'000}, "env steps per env between training phases");
  v.field("gradient_steps", c.gradient_steps, config::Range{1, 1'000'000}, "gradient steps per training phase");
}

}  // namespace rdsim
