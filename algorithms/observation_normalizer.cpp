#include "rdsim/algorithms/observation_normalizer.hpp"

#include <cmath>
#include <istream>
#include <ostream>

#include "rdsim/policy/policy_program.hpp"
#include "rdsim/core/assert.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/vecenv/observation_batch.hpp"

namespace rdsim {

ObservationNormalizer::ObservationNormalizer(int size)
    : size_(size),
      stats_(size),
      pending_(size),
      mean_(Eigen::VectorXf::Zero(size)),
      inv_std_(Eigen::VectorXf::Ones(size)) {}

void ObservationNormalizer::observe(const Eigen::MatrixXf& observations) {
  RDSIM_ASSERT(observations.rows() == size_, "observations of the normalised size");
  for (Eigen::Index c = 0; c < observations.cols(); ++c) pending_.add(observations.col(c));
}

void ObservationNormalizer::refresh(Communicator& comm) {
  stats_.merge(merge_over_ranks(comm, pending_));
  pending_.clear();
  if (stats_.count() < 2) return;
  active_ = true;
  mean_ = stats_.mean().cast<float>();
  inv_std_ = (stats_.variance().array() + epsilon).rsqrt().cast<float>().matrix();
}

void ObservationNormalizer::apply(const Eigen::MatrixXf& x, Eigen::Ref<Eigen::MatrixXf> out) const {
  RDSIM_ASSERT(enabled() && x.rows() == size_ && out.rows() == x.rows() && out.cols() == x.cols(), "inputs of the normalised size");
  if (!active_) {
    out = x;
    return;
  }
  out = ((x.colwise() - mean_).array().colwise() * inv_std_.array()).cwiseMax(-clip).cwiseMin(clip).matrix();
}

const Eigen::MatrixXf& ObservationNormalizer::network_input(const Eigen::MatrixXf& x, float input_scale,
                                                            Eigen::MatrixXf& scratch) const {
  if (!enabled()) return scaled_input(x, input_scale, scratch);
  scratch.resize(x.rows(), x.cols());
  apply(x, scratch);
  return scratch;
}

void ObservationNormalizer::add_input_ops(PolicyProgram& program, float input_scale) const {
  if (enabled()) {
    if (active_) program.standardize(mean_, inv_std_, clip);
    return;
  }
  program.scale(input_scale);
}

namespace {

void write_floats(std::ostream& out, const Eigen::VectorXf& v) {
  for (Eigen::Index i = 0; i < v.size(); ++i) write_f32(out, v[i]);
}

Eigen::VectorXf read_floats(std::istream& in, int size, const std::string& source) {
  Eigen::VectorXf v(size);
  for (int i = 0; i < size; ++i) v[i] = read_f32(in, source);
  return v;
}

}  // namespace

void ObservationNormalizer::save(std::ostream& out, bool training_state) const {
  if (!enabled()) return;
  write_u64(out, static_cast<std::uint64_t>(size_));
  write_u32(out, active_ ? 1u : 0u);
  write_floats(out, mean_);
  write_floats(out, inv_std_);
  if (!training_state) return;
  stats_.save(out);
  pending_.save(out);
}

void ObservationNormalizer::load(std::istream& in, bool training_state, const std::string& source) {
  if (!enabled()) return;
  const std::uint64_t size = read_u64(in, source);
  if (size != static_cast<std::uint64_t>(size_))
    throw Error(source + ": observation normalisation for " + std::to_string(size) + " inputs, the env has " +
                std::to_string(size_) + " (damaged file?)");
  const std::uint32_t active = read_u32(in, source);
  if (active > 1) throw Error(source + ": observation normalisation is damaged (a flag of " + std::to_string(active) + ")");
  Eigen::VectorXf mean = read_floats(in, size_, source), inv_std = read_floats(in, size_, source);
  if (!mean.allFinite() || !inv_std.allFinite() || (inv_std.array() <= 0.0f).any())
    throw Error(source + ": observation normalisation holds a non-finite mean or a non-positive scale (damaged file?)");
  active_ = active == 1;
  mean_ = std::move(mean);
  inv_std_ = std::move(inv_std);
  if (!training_state) return;
  stats_.load(in, source);
  pending_.load(in, source);
}

}  // namespace rdsim
