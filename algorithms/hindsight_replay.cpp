#include "rdsim/algorithms/hindsight_replay.hpp"

#include <cmath>
#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {
constexpr std::uint32_t kHerTag = 0x52454852;  // "RHER"
constexpr int kMaxStreams = 1'000'000;
}  // namespace

void require_goal_env(const Spec& spec, const std::string& where) {
  if (!spec.goal.active())
    throw Error(where + ": her: env \"" + spec.env_name +
                "\" is not goal-conditioned (hindsight experience replay needs goals: push, pick_and_place, stack, "
                "reach_goal)");
}

HindsightReplay::HindsightReplay(const HerConfig& config, const GoalLayout& goal, long long capacity)
    : config_(config),
      goal_(goal),
      capacity_(capacity),
      start_(static_cast<std::size_t>(capacity), 0),
      length_(static_cast<std::size_t>(capacity), 0) {
  if (!goal.active()) throw Error("HindsightReplay: the env is not goal-conditioned");
}

void HindsightReplay::added(long long slot, int stream, int streams, bool episode_end) {
  if (streams_ == 0) {
    streams_ = streams;
    open_start_.assign(static_cast<std::size_t>(streams), 0);
    open_length_.assign(static_cast<std::size_t>(streams), 0);
  } else if (streams != streams_) {
    throw Error("hindsight experience replay: transitions of " + std::to_string(streams) +
                " envs joined a buffer of " + std::to_string(streams_) + " envs' episodes");
  }
  const auto s = static_cast<std::size_t>(slot);
  // Overwriting the first transition of a finished episode: the whole episode stops being relabelled
  // (its first slot is always the first of it the ring reaches).
  if (const int old = length_[s]; old > 0) {
    const long long first = start_[s];
    for (long long k = 0; k < old; ++k) length_[static_cast<std::size_t>(slot_of(first, k))] = 0;
    relabelable_ -= old;
  }
  const auto e = static_cast<std::size_t>(stream);
  if (open_length_[e] == 0) open_start_[e] = slot;
  start_[s] = open_start_[e];
  length_[s] = 0;
  const int length = ++open_length_[e];
  if (!episode_end) return;
  open_length_[e] = 0;
  // An episode longer than the ring has lost its beginning: never relabelled.
  if (static_cast<long long>(length - 1) * streams_ >= capacity_) return;
  for (long long k = 0; k < length; ++k) length_[static_cast<std::size_t>(slot_of(start_[s], k))] = length;
  relabelable_ += length;
}

void HindsightReplay::relabel(const ReplayBuffer& buffer, long long slot, int column, Rng& rng,
                              ReplayBatch& out) const {
  const auto s = static_cast<std::size_t>(slot);
  const long long length = length_[s];
  const long long first = start_[s];
  const long long here = ((slot - first + capacity_) % capacity_) / streams_;  // step within the episode
  long long k = length - 1;
  if (config_.goal_selection_strategy == GoalSelection::Future)
    k = here + static_cast<long long>(rng.below(static_cast<std::uint64_t>(length - here)));
  else if (config_.goal_selection_strategy == GoalSelection::Episode)
    k = static_cast<long long>(rng.below(static_cast<std::uint64_t>(length)));
  buffer.copy_to(slot, column, out);
  // The new goal: what was achieved after step k.
  const float* goal = buffer.next_observation(slot_of(first, k)) + goal_.achieved_offset();
  const int n = goal_.goal_size();
  const Eigen::Index j = column;
  for (int i = 0; i < n; ++i) {
    out.observations(goal_.desired_offset() + i, j) = goal[i];
    out.next_observations(goal_.desired_offset() + i, j) = goal[i];
  }
  const float* achieved = out.next_observations.col(j).data() + goal_.achieved_offset();
  out.rewards[j] = goal_.reward_of(achieved, goal);
  out.terminated[j] = goal_.is_success(achieved, goal) ? 1.0f : 0.0f;
}

void HindsightReplay::sample(const ReplayBuffer& buffer, int batch_size, Rng& rng, ReplayBatch& out) const {
  buffer.shape_batch(batch_size, out);
  sample_into(buffer, 0, batch_size, rng, out);
}

void HindsightReplay::sample_into(const ReplayBuffer& buffer, int first, int count, Rng& rng, ReplayBatch& out,
                                  long long* slots) const {
  if (buffer.size() == 0) throw Error("ReplayBuffer::sample: the buffer is empty");
  const int relabelled = relabelable_ > 0 ? static_cast<int>(std::lround(config_.relabel_fraction() * count)) : 0;
  const auto size = static_cast<std::uint64_t>(buffer.size());
  const int end = first + count;
  for (int j = first; j < end - relabelled; ++j) {
    const auto slot = static_cast<long long>(rng.below(size));
    buffer.copy_to(slot, j, out);
    if (slots) slots[j - first] = slot;
  }
  for (int j = end - relabelled; j < end; ++j) {
    // Uniform over the relabelable transitions: the others are the running episodes and at most
    // one cut episode per env, so few draws are rejected once a few episodes are stored.
    long long slot = 0;
    do slot = static_cast<long long>(rng.below(size));
    while (length_[static_cast<std::size_t>(slot)] == 0);
    relabel(buffer, slot, j, rng, out);
    if (slots) slots[j - first] = slot;
  }
}

void HindsightReplay::save(std::ostream& out, long long filled) const {
  write_u32(out, kHerTag);
  write_u32(out, static_cast<std::uint32_t>(streams_));
  for (std::size_t e = 0; e < open_start_.size(); ++e) {
    write_u64(out, static_cast<std::uint64_t>(open_start_[e]));
    write_u32(out, static_cast<std::uint32_t>(open_length_[e]));
  }
  const auto n = static_cast<std::streamsize>(filled);
  out.write(reinterpret_cast<const char*>(start_.data()), n * static_cast<std::streamsize>(sizeof(long long)));
  out.write(reinterpret_cast<const char*>(length_.data()), n * static_cast<std::streamsize>(sizeof(int)));
}

void HindsightReplay::load(std::istream& in, long long filled, const std::string& source) {
  const auto damaged = [&] { return Error(source + ": hindsight replay bookkeeping is damaged (damaged checkpoint?)"); };
  if (read_u32(in, source) != kHerTag)
    throw Error(source + ": hindsight replay bookkeeping not found (a checkpoint of a run without \"her\"?)");
  const std::uint32_t streams = read_u32(in, source);
  if (streams > static_cast<std::uint32_t>(kMaxStreams)) throw damaged();
  std::vector<long long> open_start(streams);
  std::vector<int> open_length(streams);
  for (std::size_t e = 0; e < streams; ++e) {
    open_start[e] = static_cast<long long>(read_u64(in, source));
    open_length[e] = static_cast<int>(read_u32(in, source));
    if (open_start[e] < 0 || open_start[e] >= capacity_ || open_length[e] < 0) throw damaged();
  }
  const auto n = static_cast<std::size_t>(filled);
  std::vector<long long> start(static_cast<std::size_t>(capacity_), 0);
  std::vector<int> length(static_cast<std::size_t>(capacity_), 0);
  const auto read = [&](void* data, std::size_t bytes) {
    in.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes));
    if (in.gcount() != static_cast<std::streamsize>(bytes)) throw Error(source + ": hindsight replay bookkeeping is truncated");
  };
  read(start.data(), n * sizeof(long long));
  read(length.data(), n * sizeof(int));
  long long relabelable = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (start[i] < 0 || start[i] >= capacity_ || length[i] < 0 || (length[i] > 0 && streams == 0)) throw damaged();
    relabelable += length[i] > 0;
  }
  // Every relabelable transition's episode must lie inside the filled slots.
  for (std::size_t i = 0; i < n; ++i)
    if (length[i] > 0 && static_cast<long long>(length[i] - 1) * streams >= capacity_) throw damaged();
  streams_ = static_cast<int>(streams);
  open_start_ = std::move(open_start);
  open_length_ = std::move(open_length);
  start_ = std::move(start);
  length_ = std::move(length);
  relabelable_ = relabelable;
}

}  // namespace rdsim
