#pragma once
#include <Eigen/Core>
#include <iosfwd>
#include <string>
#include <vector>

// Running mean and variance of observations (Welford's update, Chan et al.'s merge, in double),
// to standardise a policy's inputs: ARS "V2" (Mania et al. 2018), optionally CMA-ES.
namespace rdsim {

class RunningNormalizer {
public:
  explicit RunningNormalizer(int size = 0);

  int size() const { return static_cast<int>(mean_.size()); }
  long long count() const { return count_; }

  void add(const Eigen::Ref<const Eigen::VectorXf>& x);
  // Folds in the statistics of another normaliser of the same size.
  void merge(const RunningNormalizer& other);
  void clear();

  // (x - mean) / sqrt(var + 1e-8) per entry; x unchanged while fewer than 2 observations were seen.
  void normalize(const Eigen::Ref<const Eigen::VectorXf>& x, Eigen::Ref<Eigen::VectorXf> out) const;

  const Eigen::VectorXd& mean() const { return mean_; }
  Eigen::VectorXd variance() const;  // population variance (1 while fewer than 2 observations)

  // The statistics as 1 + 2 size() doubles (count, means, sums of squared deviations), to send
  // between the ranks of an MPI job; from_doubles reads them back exactly.
  std::vector<double> to_doubles() const;
  static RunningNormalizer from_doubles(const double* values, int size);

  void save(std::ostream& out) const;
  // rdsim::Error naming `source` when the stored size differs or the stream ends early.
  void load(std::istream& in, const std::string& source);

private:
  long long count_ = 0;
  Eigen::VectorXd mean_, m2_;  // m2: sum of squared deviations from the mean
};

class Communicator;  // rdsim/parallel/communicator.hpp

// Every rank's `seen` statistics merged in rank order (one allgather): the same on every rank.
RunningNormalizer merge_over_ranks(Communicator& comm, const RunningNormalizer& seen);

}  // namespace rdsim
