#pragma once
#include <Eigen/Core>

#include "rdsim/core/rng.hpp"

namespace rdsim::nn {

// Fills `weights` (rows x cols) with a (semi-)orthogonal matrix times `gain`: the Q factor of the
// QR decomposition of a standard-normal matrix drawn from `rng`, with column signs fixed by
// diag(R) so the result is uniformly distributed. Rows (if rows <= cols) or columns (otherwise)
// are orthonormal before scaling. This is the init of the common PPO/A2C baselines.
void orthogonal_init(Eigen::MatrixXf& weights, float gain, Rng& rng);

}  // namespace rdsim::nn
