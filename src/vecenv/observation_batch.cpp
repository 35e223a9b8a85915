#include "rdsim/vecenv/observation_batch.hpp"

#include <algorithm>

#include "rdsim/core/error.hpp"

namespace rdsim {

Eigen::MatrixXf observation_batch(const std::vector<Observation>& obs, const ObservationSpace& space) {
  Eigen::MatrixXf batch(observation_input_size(space), static_cast<Eigen::Index>(obs.size()));
  for (std::size_t j = 0; j < obs.size(); ++j) encode_observation(obs[j], space, batch.col(static_cast<Eigen::Index>(j)));
  return batch;
}

void ObservationBatch::resize(const ObservationSpace& space, int envs) {
  type = space.type;
  values.setZero(space.value_count(), envs);
  pixels.setZero(space.byte_count(), envs);
}

ObservationOut ObservationBatch::column(int env) {
  return {values.rows() > 0 ? values.col(env).data() : nullptr, pixels.rows() > 0 ? pixels.col(env).data() : nullptr};
}

void ObservationBatch::copy_to(int env, Observation& out) const {
  out.values = values.col(env);
  out.pixels.assign(pixels.col(env).data(), pixels.col(env).data() + pixels.rows());
}

void ObservationBatch::assign(int env, const Observation& obs) {
  if (obs.values.size() != values.rows() || static_cast<Eigen::Index>(obs.pixels.size()) != pixels.rows())
    throw Error("observation has " + std::to_string(obs.values.size()) + " values and " + std::to_string(obs.pixels.size()) +
                " pixel bytes, the env's spec says " + std::to_string(values.rows()) + " and " + std::to_string(pixels.rows()));
  values.col(env) = obs.values;
  if (pixels.rows() > 0) std::copy(obs.pixels.begin(), obs.pixels.end(), pixels.col(env).data());
}

const Eigen::MatrixXf& network_input(const ObservationBatch& batch, Eigen::MatrixXf& scratch) {
  return network_input(batch, scratch, 0, batch.envs());
}

const Eigen::MatrixXf& network_input(const ObservationBatch& batch, Eigen::MatrixXf& scratch, int first, int count) {
  if (batch.pixels.rows() == 0) {
    if (first == 0 && count == batch.values.cols()) return batch.values;
    scratch = batch.values.middleCols(first, count);
    return scratch;
  }
  const Eigen::Index bytes = batch.pixels.rows(), values = batch.values.rows();
  scratch.resize(bytes + values, count);
  scratch.topRows(bytes) = batch.pixels.middleCols(first, count).cast<float>() * pixel_input_scale;
  if (values > 0) scratch.bottomRows(values) = batch.values.middleCols(first, count);
  return scratch;
}

void encode_observation(const ObservationBatch& batch, int env, Eigen::Ref<Eigen::VectorXf> out) {
  const Eigen::Index bytes = batch.pixels.rows(), values = batch.values.rows();
  if (bytes > 0) out.head(bytes) = batch.pixels.col(env).cast<float>() * pixel_input_scale;
  if (values > 0) out.segment(bytes, values) = batch.values.col(env);
}

const Eigen::MatrixXf& scaled_input(const Eigen::MatrixXf& batch, float scale, Eigen::MatrixXf& scratch) {
  if (scale == 1.0f) return batch;
  scratch.noalias() = batch * scale;
  return scratch;
}

}  // namespace rdsim
