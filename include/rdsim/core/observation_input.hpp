#pragma once
#include <Eigen/Core>

#include "rdsim/core/env.hpp"

// How one observation becomes network input: UInt8 pixels (HWC) scaled to [0, 1] (times
// pixel_input_scale) and flattened in storage order, then the Float32 values as they are (a
// vector, a Float32 image, then the vector beside an image). Shared by training
// (vecenv/observation_batch.hpp batches it) and the policy library.
namespace rdsim {

inline constexpr float pixel_input_scale = 1.0f / 255.0f;

// Number of network inputs for observations of this space.
int observation_input_size(const ObservationSpace& space);

// rdsim::Error when `obs` does not have the space's sizes.
void encode_observation(const Observation& obs, const ObservationSpace& space, Eigen::Ref<Eigen::VectorXf> out);

}  // namespace rdsim
