#pragma once
#include <Eigen/Core>
#include <iosfwd>
#include <string>

#include "rdsim/rng.hpp"

// Experience replay for off-policy learning (DQN): a ring of transitions in preallocated
// column-per-sample storage, so adding and sampling never allocate.
namespace rdsim {

// A sampled minibatch, one column/entry per transition.
struct ReplayBatch {
  Eigen::MatrixXf observations;       // obs_size x batch
  Eigen::VectorXi actions;            // batch
  Eigen::VectorXf rewards;            // batch
  Eigen::MatrixXf next_observations;  // obs_size x batch
  Eigen::VectorXf terminated;         // batch; 1 = no bootstrap (the MDP ended), 0 otherwise
};

class ReplayBuffer {
public:
  // Throws rdsim::Error for a non-positive capacity or observation size.
  ReplayBuffer(long long capacity, int observation_size);

  // Stores one transition, overwriting the oldest when full. For an episode cut by the step
  // limit pass the final observation as `next_observation` and terminated = false, so its
  // value is bootstrapped; a terminated transition is never bootstrapped.
  void add(const Eigen::Ref<const Eigen::VectorXf>& observation, int action, float reward,
           const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated);

  long long size() const { return size_; }
  long long capacity() const { return capacity_; }
  int observation_size() const { return static_cast<int>(observations_.rows()); }

  // `batch_size` transitions drawn uniformly with replacement (rng.below). `out` is resized
  // only when its shape changes. Throws rdsim::Error when the buffer is empty.
  void sample(int batch_size, Rng& rng, ReplayBatch& out) const;

  // The stored transitions and ring position (checkpoints). load() throws rdsim::Error naming
  // `source` when capacity or observation size differ from this buffer's.
  void save(std::ostream& out) const;
  void load(std::istream& in, const std::string& source);

private:
  long long capacity_;
  long long size_ = 0;
  long long next_ = 0;  // slot the next add() writes
  Eigen::MatrixXf observations_, next_observations_;
  Eigen::VectorXi actions_;
  Eigen::VectorXf rewards_, terminated_;
};

}  // namespace rdsim
