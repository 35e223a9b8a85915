#include "rdsim/algorithms/running_normalizer.hpp"

#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/parallel/communicator.hpp"

namespace rdsim {

RunningNormalizer::RunningNormalizer(int size) : mean_(Eigen::VectorXd::Zero(size)), m2_(Eigen::VectorXd::Zero(size)) {}

void RunningNormalizer::add(const Eigen::Ref<const Eigen::VectorXf>& x) {
  if (x.size() != mean_.size()) throw Error("RunningNormalizer: observation of the wrong size");
  ++count_;
  const Eigen::VectorXd xd = x.cast<double>();
  const Eigen::VectorXd delta = xd - mean_;
  mean_ += delta / static_cast<double>(count_);
  m2_.array() += delta.array() * (xd - mean_).array();
}

void RunningNormalizer::merge(const RunningNormalizer& other) {
  if (other.size() != size()) throw Error("RunningNormalizer: merging statistics of different sizes");
  if (other.count_ == 0) return;
  const double n_a = static_cast<double>(count_), n_b = static_cast<double>(other.count_), n = n_a + n_b;
  const Eigen::VectorXd delta = other.mean_ - mean_;
  mean_ += delta * (n_b / n);
  m2_ += other.m2_ + delta.cwiseProduct(delta) * (n_a * n_b / n);
  count_ += other.count_;
}

void RunningNormalizer::clear() {
  count_ = 0;
  mean_.setZero();
  m2_.setZero();
}

Eigen::VectorXd RunningNormalizer::variance() const {
  if (count_ < 2) return Eigen::VectorXd::Ones(size());
  return m2_ / static_cast<double>(count_);
}

void RunningNormalizer::normalize(const Eigen::Ref<const Eigen::VectorXf>& x, Eigen::Ref<Eigen::VectorXf> out) const {
  if (count_ < 2) {
    out = x;
    return;
  }
  out = ((x.cast<double>() - mean_).array() / (variance().array() + 1e-8).sqrt()).cast<float>().matrix();
}

std::vector<double> RunningNormalizer::to_doubles() const {
  std::vector<double> values(1 + 2 * static_cast<std::size_t>(size()));
  values[0] = static_cast<double>(count_);  // exact: counts stay far below 2^53
  for (int i = 0; i < size(); ++i) {
    values[1 + static_cast<std::size_t>(i)] = mean_[i];
    values[1 + static_cast<std::size_t>(size() + i)] = m2_[i];
  }
  return values;
}

RunningNormalizer RunningNormalizer::from_doubles(const double* values, int size) {
  RunningNormalizer n(size);
  n.count_ = static_cast<long long>(values[0]);
  for (int i = 0; i < size; ++i) {
    n.mean_[i] = values[1 + i];
    n.m2_[i] = values[1 + size + i];
  }
  return n;
}

void RunningNormalizer::save(std::ostream& out) const {
  write_u32(out, static_cast<std::uint32_t>(size()));
  write_u64(out, static_cast<std::uint64_t>(count_));
  for (int i = 0; i < size(); ++i) {
    write_f64(out, mean_[i]);
    write_f64(out, m2_[i]);
  }
}

void RunningNormalizer::load(std::istream& in, const std::string& source) {
  const std::uint32_t n = read_u32(in, source);
  if (n != static_cast<std::uint32_t>(size()))
    throw Error(source + ": observation statistics of " + std::to_string(n) + " values, expected " +
                std::to_string(size()) + " (a different env?)");
  const std::uint64_t count_bits = read_u64(in, source);
  if (count_bits > (1ull << 50)) throw Error(source + ": observation statistics hold a count out of range (damaged file?)");
  const auto count = static_cast<long long>(count_bits);
  Eigen::VectorXd mean(n), m2(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    mean[i] = read_f64(in, source);
    m2[i] = read_f64(in, source);
  }
  if (!mean.allFinite() || !m2.allFinite() || (m2.array() < 0.0).any())
    throw Error(source + ": observation statistics hold damaged values (damaged file?)");
  count_ = count;
  mean_ = mean;
  m2_ = m2;
}

RunningNormalizer merge_over_ranks(Communicator& comm, const RunningNormalizer& seen) {
  if (comm.size() == 1) return seen;
  const std::vector<double> mine = seen.to_doubles();
  std::vector<double> all(mine.size() * static_cast<std::size_t>(comm.size()));
  comm.allgather(mine.data(), mine.size(), all.data());
  RunningNormalizer merged(seen.size());
  for (int r = 0; r < comm.size(); ++r)
    merged.merge(RunningNormalizer::from_doubles(all.data() + static_cast<std::size_t>(r) * mine.size(), seen.size()));
  return merged;
}

}  // namespace rdsim
