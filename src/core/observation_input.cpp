#include "rdsim/core/observation_input.hpp"

#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim {

int observation_input_size(const ObservationSpace& space) { return space.size() + space.vector_size; }

void encode_observation(const Observation& obs, const ObservationSpace& space, Eigen::Ref<Eigen::VectorXf> out) {
  const int values = space.value_count(), bytes = space.byte_count();
  if (obs.values.size() != values) {
    throw Error("observation has " + std::to_string(obs.values.size()) + " values, the env's spec says " +
                std::to_string(values));
  }
  if (static_cast<int>(obs.pixels.size()) != bytes) {
    throw Error("observation has " + std::to_string(obs.pixels.size()) + " pixels bytes, the env's spec says " +
                std::to_string(bytes));
  }
  for (int i = 0; i < bytes; ++i) out[i] = static_cast<float>(obs.pixels[static_cast<std::size_t>(i)]) * pixel_input_scale;
  out.segment(bytes, values) = obs.values;
}

}  // namespace rdsim
