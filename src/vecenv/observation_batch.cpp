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
  if (type == ObsType::Float32) {
    values.setZero(space.size(), envs);
    pixels.resize(0, 0);
  } else {
    pixels.setZero(space.size(), envs);
    values.resize(0, 0);
  }
}

ObservationOut ObservationBatch::column(int env) {
  if (type == ObsType::Float32) return {values.col(env).data(), nullptr};
  return {nullptr, pixels.col(env).data()};
}

void ObservationBatch::copy_to(int env, Observation& out) const {
  if (type == ObsType::Float32) {
    out.values = values.col(env);
    out.pixels.clear();
  } else {
    out.values.resize(0);
    out.pixels.assign(pixels.col(env).data(), pixels.col(env).data() + pixels.rows());
  }
}

void ObservationBatch::assign(int env, const Observation& obs) {
  ObservationSpace space;
  space.type = type;
  space.shape = {static_cast<int>(type == ObsType::Float32 ? values.rows() : pixels.rows())};
  copy_observation(obs, space, column(env));
}

const Eigen::MatrixXf& network_input(const ObservationBatch& batch, Eigen::MatrixXf& scratch) {
  return network_input(batch, scratch, 0, batch.type == ObsType::Float32 ? static_cast<int>(batch.values.cols())
                                                                          : static_cast<int>(batch.pixels.cols()));
}

const Eigen::MatrixXf& network_input(const ObservationBatch& batch, Eigen::MatrixXf& scratch, int first, int count) {
  if (batch.type == ObsType::Float32) {
    if (first == 0 && count == batch.values.cols()) return batch.values;
    scratch = batch.values.middleCols(first, count);
  } else {
    scratch = batch.pixels.middleCols(first, count).cast<float>() * pixel_input_scale;
  }
  return scratch;
}

void encode_observation(const ObservationBatch& batch, int env, Eigen::Ref<Eigen::VectorXf> out) {
  if (batch.type == ObsType::Float32)
    out = batch.values.col(env);
  else
    out = batch.pixels.col(env).cast<float>() * pixel_input_scale;
}

const Eigen::MatrixXf& scaled_input(const Eigen::MatrixXf& batch, float scale, Eigen::MatrixXf& scratch) {
  if (scale == 1.0f) return batch;
  scratch.noalias() = batch * scale;
  return scratch;
}

}  // namespace rdsim
