#include "rdsim/core/observation_input.hpp"

#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim {

int observation_input_size(const ObservationSpace& space) { return space.size(); }

void encode_observation(const Observation& obs, const ObservationSpace& space, Eigen::Ref<Eigen::VectorXf> out) {
  const int n = space.size();
  if (space.type == ObsType::Float32) {
    if (obs.values.size() != n) {
      throw Error("observation has " + std::to_string(obs.values.size()) + " values, the env's spec says " +
                  std::to_string(n));
    }
    out = obs.values;
    return;
  }
  if (static_cast<int>(obs.pixels.size()) != n) {
    throw Error("observation has " + std::to_string(obs.pixels.size()) + " pixels bytes, the env's spec says " +
                std::to_string(n));
  }
  for (int i = 0; i < n; ++i) out[i] = static_cast<float>(obs.pixels[static_cast<std::size_t>(i)]) * pixel_input_scale;
}

}  // namespace rdsim
