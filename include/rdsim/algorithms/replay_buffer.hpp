#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// Experience replay for off-policy learning (DQN, SAC, TD3/DDPG): a ring of transitions in
// preallocated column-per-sample storage, so adding and sampling never allocate. Actions are
// Discrete indices or Box vectors (`action_dim` floats, stored as the algorithm passes them, e.g.
// rescaled to [-1, 1]).
namespace rdsim {

// A sampled minibatch, one column/entry per transition, in network-input form (pixels scaled
// to [0, 1] exactly as encode_observation does).
struct ReplayBatch {
  Eigen::MatrixXf observations;       // obs_size x batch
  Eigen::VectorXi actions;            // batch (Discrete actions)
  Eigen::MatrixXf action_values;      // action_dim x batch (Box actions)
  Eigen::VectorXf rewards;            // batch
  Eigen::MatrixXf next_observations;  // obs_size x batch
  Eigen::VectorXf terminated;         // batch; 1 = no bootstrap (the MDP ended), 0 otherwise
  Eigen::VectorXf steps;              // batch; env steps the reward sums (n-step returns; 1 otherwise):
                                      // the bootstrap is discounted by gamma^steps
};

class ReplayBuffer {
public:
  using Bytes = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>;

  // Float32 storage of `observation_size` values per observation. action_dim 0: Discrete
  // actions (indices); > 0: Box actions of that many floats. Throws rdsim::Error for a
  // non-positive capacity or observation size, or a negative action_dim.
  ReplayBuffer(long long capacity, int observation_size, int action_dim = 0);
  // Storage that follows the space: UInt8 (pixel) observations are kept as bytes, 4x smaller
  // than floats, which is what makes a pixel buffer of useful size fit in memory.
  ReplayBuffer(long long capacity, const ObservationSpace& space, int action_dim = 0);

  // Stores one transition, overwriting the oldest when full. For an episode cut by the step
  // limit pass the final observation as `next_observation` and terminated = false, so its
  // value is bootstrapped; a terminated transition is never bootstrapped.
  // This overload takes network-input floats and needs Float32 storage.
  void add(const Eigen::Ref<const Eigen::VectorXf>& observation, int action, float reward,
           const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated);
  // Env observations as they come (values or pixels, matching the storage type). `steps` > 1:
  // an n-step transition (n_step_returns.hpp), `reward` the discounted sum of that many rewards and
  // `next_observation` the observation that many steps later (or where the episode ended).
  void add(const Observation& observation, int action, float reward, const Observation& next_observation,
           bool terminated, int steps = 1);
  // Box actions (action_dim > 0): `action` holds action_dim values.
  void add(const Eigen::Ref<const Eigen::VectorXf>& observation, const Eigen::Ref<const Eigen::VectorXf>& action,
           float reward, const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated);
  void add(const Observation& observation, const Eigen::Ref<const Eigen::VectorXf>& action, float reward,
           const Observation& next_observation, bool terminated);

  long long size() const { return size_; }
  long long capacity() const { return capacity_; }
  int observation_size() const { return observation_size_; }
  int action_dim() const { return action_dim_; }  // 0: Discrete actions
  bool stores_pixels() const { return pixels_; }
  // The largest action index stored (-1 when empty or the actions are Box vectors).
  int largest_action() const;
  // Bytes held by the stored observations (both observation and next observation).
  std::size_t observation_bytes() const;

  // `batch_size` transitions drawn uniformly with replacement (rng.below). `out` is resized
  // only when its shape changes. Throws rdsim::Error when the buffer is empty.
  void sample(int batch_size, Rng& rng, ReplayBatch& out) const;
  // The same draws into columns [first, first + count) of `out`, already shaped (shape_batch).
  // `slots` (when given, `count` of them): the slot each column was drawn from.
  void sample_into(int first, int count, Rng& rng, ReplayBatch& out, long long* slots = nullptr) const;

  // The pieces of sample() for samplers of their own (hindsight_replay.hpp): the slot the latest
  // add() wrote, `out` shaped for `batch_size` transitions (resized only when its shape changes),
  // the transition in `slot` copied into column `column`, and a stored next observation as it was
  // added (Float32 storage only: observation_size() values).
  long long last_slot() const { return (next_ + capacity_ - 1) % capacity_; }
  void shape_batch(int batch_size, ReplayBatch& out) const;
  void copy_to(long long slot, int column, ReplayBatch& out) const;
  const float* next_observation(long long slot) const;

  // The stored transitions and ring position (checkpoints). load() throws rdsim::Error naming
  // `source` when capacity, observation size, action kind or storage type differ from this buffer's,
  // or the stored values are damaged (not finite, actions out of range, terminated flags other than
  // 0/1, step counts below 1). A buffer of one-step transitions is saved as before n-step returns
  // existed, so older checkpoints load and one-step checkpoints keep their size.
  void save(std::ostream& out) const;
  void load(std::istream& in, const std::string& source);

private:
  void store_observations(const Observation& observation, const Observation& next_observation);
  void store_observations(const Eigen::Ref<const Eigen::VectorXf>& observation,
                          const Eigen::Ref<const Eigen::VectorXf>& next_observation);
  void store_action(const Eigen::Ref<const Eigen::VectorXf>& action);
  void store_rest(int action, float reward, bool terminated, int steps = 1);

  long long capacity_;
  long long size_ = 0;
  long long next_ = 0;  // slot the next add() writes
  int observation_size_;
  int action_dim_;
  bool pixels_ = false;
  Eigen::MatrixXf observations_, next_observations_;  // Float32 storage
  Bytes pixel_obs_, next_pixel_obs_;                   // UInt8 storage
  Eigen::VectorXi actions_;        // Discrete
  Eigen::MatrixXf action_values_;  // Box: action_dim x capacity
  Eigen::VectorXf rewards_, terminated_;
  Eigen::VectorXf steps_;  // per transition, see ReplayBatch::steps
  bool multi_step_ = false;  // some transition has steps > 1 (saved with its steps only then)
};

}  // namespace rdsim
