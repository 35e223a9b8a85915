#pragma once
#include <Eigen/Core>
#include <vector>

#include "rdsim/core/env.hpp"

// How observations become network input: Float32 vectors as they are; UInt8 pixels (HWC)
// scaled to [0, 1] and flattened in storage order. One column per observation.
namespace rdsim {

// Number of network inputs for observations of this space.
int observation_input_size(const ObservationSpace& space);

void encode_observation(const Observation& obs, const ObservationSpace& space, Eigen::Ref<Eigen::VectorXf> out);

Eigen::MatrixXf observation_batch(const std::vector<Observation>& obs, const ObservationSpace& space);

// network.input_scale: `batch` times `scale`, written to `scratch`, or `batch` itself at scale 1
// (no copy on the common path).
const Eigen::MatrixXf& scaled_input(const Eigen::MatrixXf& batch, float scale, Eigen::MatrixXf& scratch);

}  // namespace rdsim
