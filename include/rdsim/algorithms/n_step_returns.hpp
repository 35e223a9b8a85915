#pragma once
#include <deque>
#include <iosfwd>
#include <string>
#include <vector>

#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/core/env.hpp"

// n-step returns for replay-based Q-learning (Sutton 1988; Hessel et al. 2018, "Rainbow"): instead
// of (s_t, a_t, r_t, s_t+1), the buffer receives (s_t, a_t, r_t + g r_t+1 + ... + g^(n-1) r_t+n-1,
// s_t+n) with the bootstrap discounted by g^n, so a reward reaches the value of a state n steps
// back in one backup. Each env's last n steps wait here until their n-step return is known; an
// episode's end writes them all out with the rewards up to the end (terminated: no bootstrap;
// truncated: bootstrap from the final observation, discounted by g^(steps left)). With n = 1 every
// transition goes straight through, exactly as without this class.
namespace rdsim {

class NStepReturns {
public:
  // `space`: the env's observations (what load() checks the saved ones against).
  NStepReturns(int n, double gamma, const ObservationSpace& space);

  int n() const { return n_; }

  // Env `env`'s step: from `observation`, `action` gave `reward` and `next_observation` (the final
  // observation when the episode ended: `done`, with `terminated` when the MDP ended). Adds to
  // `buffer` every transition whose return is complete. Envs are numbered from 0 (a VecEnv's order).
  void add(int env, const Observation& observation, int action, float reward, const Observation& next_observation,
           bool terminated, bool done, ReplayBuffer& buffer);

  // The waiting steps (training checkpoints, so a resumed run continues bit for bit). load()
  // throws rdsim::Error naming `source` for a different n or observation size, or damaged data.
  void save(std::ostream& out) const;
  void load(std::istream& in, const std::string& source);

private:
  struct Pending {
    Observation observation;
    int action = 0;
    float reward = 0.0f;
  };
  // Writes env's oldest waiting step with the rewards of every waiting step, bootstrapping from
  // `next_observation`.
  void emit_front(std::deque<Pending>& queue, const Observation& next_observation, bool terminated,
                  ReplayBuffer& buffer) const;

  int n_;
  double gamma_;
  ObservationSpace space_;
  std::vector<std::deque<Pending>> pending_;  // per env, oldest first, at most n - 1 between steps
};

}  // namespace rdsim
