#pragma once
#include <cstdint>
#include <iosfwd>
#include <string>

#include "rdsim/core/rng.hpp"

// What every robot env's saved state (EnvState) starts with: a tag saying which kind of env wrote
// it, the env's name, its random stream, the episode's step counter and whether the episode has
// ended. Shared by the reaching envs (reach_env.cpp) and the manipulation tasks
// (manipulation/manipulation_env.cpp), which write their own fields after it.
namespace rdsim {

struct EpisodeCounters {
  Rng rng;
  int steps = 0;
  bool done = true;
};

void write_episode_header(std::ostream& out, std::uint32_t tag, const std::string& env_name, const Rng& rng, int steps,
                          bool done);

// The header written above; rdsim::Error naming `source` for a state of another kind of env (`kind`,
// e.g. "a reaching env's"), of another env, or with counters out of range (steps above max_steps).
EpisodeCounters read_episode_header(std::istream& in, std::uint32_t tag, const char* kind, const std::string& env_name,
                                    int max_steps, const std::string& source);

}  // namespace rdsim
