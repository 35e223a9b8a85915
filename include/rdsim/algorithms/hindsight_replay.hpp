#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/goal_layout.hpp"
#include "rdsim/core/rng.hpp"

// Hindsight experience replay over a ReplayBuffer of goal-env transitions: which episode each
// stored transition belongs to, and minibatches in which n_sampled_goal / (n_sampled_goal + 1) of
// the transitions get a goal achieved later in their own episode (her.hpp), the reward the goal
// layout gives for it, and terminated where that goal is reached (rdsim's goal envs end an episode
// at its goal, panda-gym's rule).
//
// The envs of a VecEnv add one transition each per step, in env order, so env i's transitions lie
// `streams` slots apart in the ring and the k-th transition of an episode starting in slot s is in
// slot (s + k * streams) mod capacity: episodes of different envs never mix. Only whole, finished
// episodes are relabelled: a running one has no future yet, and an episode whose first transition
// is overwritten by the ring stops being relabelled at that moment. Real transitions are drawn from
// the whole buffer, as without HER.
namespace rdsim {

// rdsim::Error naming `where` (the config file) when `spec`'s env has no goals to relabel.
void require_goal_env(const Spec& spec, const std::string& where);

class HindsightReplay {
public:
  // `capacity`: the buffer's. Throws rdsim::Error when `goal` is not active.
  HindsightReplay(const HerConfig& config, const GoalLayout& goal, long long capacity);

  // The transition in `slot` was just added by stream `stream` of `streams` (env i of n);
  // `episode_end`: it was its episode's last. Throws rdsim::Error when the stream count changes.
  void added(long long slot, int stream, int streams, bool episode_end);

  // `batch_size` transitions of `buffer` (the one added() followed) into `out`: real ones first,
  // drawn uniformly, then the relabelled ones (none before an episode has finished).
  void sample(const ReplayBuffer& buffer, int batch_size, Rng& rng, ReplayBatch& out) const;
  // The same for columns [first, first + count) of `out`, already shaped (ReplayBuffer::shape_batch).
  // `slots` (when given, `count` of them): the slot of each column's transition.
  void sample_into(const ReplayBuffer& buffer, int first, int count, Rng& rng, ReplayBatch& out,
                   long long* slots = nullptr) const;

  // Transitions that can be relabelled now (in finished, whole episodes).
  long long relabelable() const { return relabelable_; }
  const HerConfig& config() const { return config_; }

  // The bookkeeping of the first `filled` slots (the buffer's size) and of the running episodes
  // (checkpoints); load() throws rdsim::Error naming `source` for values that cannot be.
  void save(std::ostream& out, long long filled) const;
  void load(std::istream& in, long long filled, const std::string& source);

private:
  long long slot_of(long long start, long long k) const { return (start + k * streams_) % capacity_; }
  void relabel(const ReplayBuffer& buffer, long long slot, int column, Rng& rng, ReplayBatch& out) const;

  HerConfig config_;
  GoalLayout goal_;
  long long capacity_;
  int streams_ = 0;  // envs adding in turn; 0 until the first add
  std::vector<long long> start_;  // per slot: the slot of its episode's first transition
  std::vector<int> length_;       // per slot: its episode's length once finished and whole, else 0
  std::vector<long long> open_start_;  // per stream: the running episode's first slot
  std::vector<int> open_length_;       // per stream: its transitions so far
  long long relabelable_ = 0;
};

}  // namespace rdsim
