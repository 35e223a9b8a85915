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
  const auto values = static_cast<std::size_t>(space.value_count());
  const auto bytes = static_cast<std::size_t>(space.byte_count());
  if (static_cast<std::size_t>(obs.values.size()) != values || (values > 0 && !out.values))
    throw Error("observation has " + std::to_string(obs.values.size()) + " values, the env's spec says " +
                std::to_string(values));
  if (obs.pixels.size() != bytes || (bytes > 0 && !out.pixels))
    throw Error("observation has " + std::to_string(obs.pixels.size()) + " pixel bytes, the env's spec says " +
                std::to_string(bytes));
  std::copy_n(obs.values.data(), values, out.values);
  std::copy_n(obs.pixels.data(), bytes, out.pixels);
}

Observation make_observation(const ObservationSpace& space) {
  Observation obs;
  obs.values.resize(space.value_count());
  obs.pixels.resize(static_cast<std::size_t>(space.byte_count()));
  return obs;
}

ObservationOut observation_out(Observation& obs) {
  return {obs.values.size() > 0 ? obs.values.data() : nullptr, obs.pixels.empty() ? nullptr : obs.pixels.data()};
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
