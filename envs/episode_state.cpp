#include "rdsim/envs/episode_state.hpp"

#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"

namespace rdsim {

void write_episode_header(std::ostream& out, std::uint32_t tag, const std::string& env_name, const Rng& rng, int steps,
                          bool done) {
  write_u32(out, tag);
  write_string(out, env_name);
  write_string(out, rng_to_bytes(rng));
  write_u32(out, static_cast<std::uint32_t>(steps));
  write_u32(out, done ? 1 : 0);
}

EpisodeCounters read_episode_header(std::istream& in, std::uint32_t tag, const char* kind, const std::string& env_name,
                                    int max_steps, const std::string& source) {
  if (read_u32(in, source) != tag) throw Error(source + ": env state is not " + kind);
  const std::string name = read_string(in, source);
  if (name != env_name) throw Error(source + ": env state is of " + one_line(name, 40) + ", this env is " + env_name);
  EpisodeCounters c{.rng = rng_from_bytes(read_string(in, source), source)};
  const auto steps = static_cast<int>(read_u32(in, source));
  const std::uint32_t done = read_u32(in, source);
  if (steps < 0 || steps > max_steps || done > 1)
    throw Error(source + ": env state of " + env_name + " is damaged (counters out of range)");
  c.steps = steps;
  c.done = done != 0;
  return c;
}

}  // namespace rdsim
