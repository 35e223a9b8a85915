#include "rdsim/core/env.hpp"

#include <algorithm>
#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim {

std::pair<int, int> ObservationSpace::part(const std::string& name) const {
  int at = 0;
  for (const ObservationPart& p : parts) {
    if (p.name == name) return {at, p.size};
    at += p.size;
  }
  return {-1, 0};
}

std::string ObservationSpace::part_names() const {
  std::string list;
  for (const ObservationPart& p : parts) list += (list.empty() ? "" : ", ") + p.name;
  return list;
}

void copy_observation(const Observation& obs, const ObservationSpace& space, ObservationOut out) {
  const auto n = static_cast<std::size_t>(space.size());
  if (space.type == ObsType::Float32) {
    if (static_cast<std::size_t>(obs.values.size()) != n || !out.values)
      throw Error("observation has " + std::to_string(obs.values.size()) + " values, the env's spec says " +
                  std::to_string(n));
    std::copy_n(obs.values.data(), n, out.values);
    return;
  }
  if (obs.pixels.size() != n || !out.pixels)
    throw Error("observation has " + std::to_string(obs.pixels.size()) + " pixel bytes, the env's spec says " +
                std::to_string(n));
  std::copy_n(obs.pixels.data(), n, out.pixels);
}

Observation make_observation(const ObservationSpace& space) {
  Observation obs;
  if (space.type == ObsType::Float32)
    obs.values.resize(space.size());
  else
    obs.pixels.resize(static_cast<std::size_t>(space.size()));
  return obs;
}

ObservationOut observation_out(Observation& obs) {
  if (!obs.pixels.empty()) return {nullptr, obs.pixels.data()};
  return {obs.values.data(), nullptr};
}

void Env::reset_into(ObservationOut out, std::optional<std::uint64_t> seed) {
  copy_observation(reset(seed), spec().observation, out);
}

StepOutcome Env::step_into(const Action& action, ObservationOut out) {
  StepResult r = step(action);
  copy_observation(r.observation, spec().observation, out);
  return {r.reward, r.terminated, r.truncated, r.info};
}

StepOutcome Env::finish_step(ObservationOut /*out*/) {
  throw Error(spec().env_name + ": finish_step without a step begun (this env does not split steps)");
}

Observation reset_through_into(Env& env, std::optional<std::uint64_t> seed) {
  Observation obs = make_observation(env.spec().observation);
  env.reset_into(observation_out(obs), seed);
  return obs;
}

StepResult step_through_into(Env& env, const Action& action) {
  return step_result(env.spec().observation, [&](ObservationOut out) { return env.step_into(action, out); });
}

}  // namespace rdsim
