#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/observation_input.hpp"

// Batches of network input (core/observation_input.hpp says how one observation becomes it):
// one column per observation.
namespace rdsim {

Eigen::MatrixXf observation_batch(const std::vector<Observation>& obs, const ObservationSpace& space);

// The current observation of every env of a VecEnv, one column per env, in the env's own element
// type. Envs write straight into their column (Env::step_into), so a batch step copies nothing.
struct ObservationBatch {
  using Bytes = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>;
  ObsType type = ObsType::Float32;
  Eigen::MatrixXf values;  // value_count() x envs: Float32 vectors or images, the vector beside an image
  Bytes pixels;            // byte_count() x envs, each column one HWC image (UInt8 spaces; empty otherwise)

  void resize(const ObservationSpace& space, int envs);
  int envs() const { return static_cast<int>(std::max(values.cols(), pixels.cols())); }
  // Where env `env` writes its observation.
  ObservationOut column(int env);
  // Env `env`'s observation as an Observation: a copy into `out`, reusing its storage.
  void copy_to(int env, Observation& out) const;
  // Replaces env `env`'s column; rdsim::Error when `obs` does not fit it.
  void assign(int env, const Observation& obs);
};

// Network input for every env of `batch` (one column each): a Float32 batch itself (no copy), one
// with pixels scaled to [0, 1] (then its values) into `scratch`, bit for bit as encode_observation does.
const Eigen::MatrixXf& network_input(const ObservationBatch& batch, Eigen::MatrixXf& scratch);
// The same for envs [first, first + count) (a copy into `scratch` unless that is every env).
const Eigen::MatrixXf& network_input(const ObservationBatch& batch, Eigen::MatrixXf& scratch, int first, int count);
// The network input of env `env` alone.
void encode_observation(const ObservationBatch& batch, int env, Eigen::Ref<Eigen::VectorXf> out);

// network.input_scale: `batch` times `scale`, written to `scratch`, or `batch` itself at scale 1
// (no copy on the common path).
const Eigen::MatrixXf& scaled_input(const Eigen::MatrixXf& batch, float scale, Eigen::MatrixXf& scratch);

}  // namespace rdsim
