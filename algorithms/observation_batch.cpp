#include "rdsim/algorithms/observation_batch.hpp"

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
  for (int i = 0; i < n; ++i) out[i] = static_cast<float>(obs.pixels[static_cast<std::size_t>(i)]) * (1.0f / 255.0f);
}

Eigen::MatrixXf observation_batch(const std::vector<Observation>& obs, const ObservationSpace& space) {
  Eigen::MatrixXf batch(observation_input_size(space), static_cast<Eigen::Index>(obs.size()));
  for (std::size_t j = 0; j < obs.size(); ++j) encode_observation(obs[j], space, batch.col(static_cast<Eigen::Index>(j)));
  return batch;
}

const Eigen::MatrixXf& scaled_input(const Eigen::MatrixXf& batch, float scale, Eigen::MatrixXf& scratch) {
  if (scale == 1.0f) return batch;
  scratch.noalias() = batch * scale;
  return scratch;
}

}  // namespace rdsim
