#include "rdsim/replay_buffer.hpp"

#include <istream>
#include <ostream>

#include "rdsim/error.hpp"
#include "rdsim/nn/serialize.hpp"

namespace rdsim {

namespace {
constexpr std::uint32_t kReplayTag = 0x50524452;  // "RDRP"
}

ReplayBuffer::ReplayBuffer(long long capacity, int observation_size) : capacity_(capacity) {
  if (capacity <= 0 || observation_size <= 0)
    throw Error("ReplayBuffer: capacity and observation size must be positive");
  const auto n = static_cast<Eigen::Index>(capacity);
  observations_.resize(observation_size, n);
  next_observations_.resize(observation_size, n);
  actions_.resize(n);
  rewards_.resize(n);
  terminated_.resize(n);
}

void ReplayBuffer::add(const Eigen::Ref<const Eigen::VectorXf>& observation, int action, float reward,
                       const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated) {
  if (observation.size() != observations_.rows() || next_observation.size() != observations_.rows())
    throw Error("ReplayBuffer::add: observation size " + std::to_string(observation.size()) +
                ", expected " + std::to_string(observations_.rows()));
  const auto i = static_cast<Eigen::Index>(next_);
  observations_.col(i) = observation;
  next_observations_.col(i) = next_observation;
  actions_[i] = action;
  rewards_[i] = reward;
  terminated_[i] = terminated ? 1.0f : 0.0f;
  next_ = (next_ + 1) % capacity_;
  if (size_ < capacity_) ++size_;
}

void ReplayBuffer::sample(int batch_size, Rng& rng, ReplayBatch& out) const {
  if (size_ == 0) throw Error("ReplayBuffer::sample: the buffer is empty");
  const Eigen::Index rows = observations_.rows();
  if (out.observations.rows() != rows || out.observations.cols() != batch_size) {
    out.observations.resize(rows, batch_size);
    out.next_observations.resize(rows, batch_size);
    out.actions.resize(batch_size);
    out.rewards.resize(batch_size);
    out.terminated.resize(batch_size);
  }
  for (int j = 0; j < batch_size; ++j) {
    const auto i = static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(size_)));
    out.observations.col(j) = observations_.col(i);
    out.next_observations.col(j) = next_observations_.col(i);
    out.actions[j] = actions_[i];
    out.rewards[j] = rewards_[i];
    out.terminated[j] = terminated_[i];
  }
}

void ReplayBuffer::save(std::ostream& out) const {
  nn::write_u32(out, kReplayTag);
  nn::write_u64(out, static_cast<std::uint64_t>(capacity_));
  nn::write_u32(out, static_cast<std::uint32_t>(observations_.rows()));
  nn::write_u64(out, static_cast<std::uint64_t>(size_));
  nn::write_u64(out, static_cast<std::uint64_t>(next_));
  // Only the filled slots: a young buffer with a large capacity stays small on disk.
  const auto n = static_cast<Eigen::Index>(size_);
  const auto bytes = [](Eigen::Index count) { return static_cast<std::streamsize>(count * 4); };
  out.write(reinterpret_cast<const char*>(observations_.data()), bytes(observations_.rows() * n));
  out.write(reinterpret_cast<const char*>(next_observations_.data()), bytes(observations_.rows() * n));
  out.write(reinterpret_cast<const char*>(actions_.data()), bytes(n));
  out.write(reinterpret_cast<const char*>(rewards_.data()), bytes(n));
  out.write(reinterpret_cast<const char*>(terminated_.data()), bytes(n));
}

void ReplayBuffer::load(std::istream& in, const std::string& source) {
  if (nn::read_u32(in, source) != kReplayTag) throw Error(source + ": replay buffer not found (damaged checkpoint?)");
  const auto capacity = static_cast<long long>(nn::read_u64(in, source));
  const auto rows = static_cast<Eigen::Index>(nn::read_u32(in, source));
  if (capacity != capacity_ || rows != observations_.rows())
    throw Error(source + ": replay buffer of capacity " + std::to_string(capacity) + " x " +
                std::to_string(rows) + " observation values, expected " + std::to_string(capacity_) +
                " x " + std::to_string(observations_.rows()) + " (different dqn.buffer_size or env?)");
  const auto size = static_cast<long long>(nn::read_u64(in, source));
  const auto next = static_cast<long long>(nn::read_u64(in, source));
  if (size < 0 || size > capacity_ || next < 0 || next >= capacity_)
    throw Error(source + ": damaged replay buffer");
  const auto n = static_cast<Eigen::Index>(size);
  const auto read = [&](void* data, Eigen::Index count) {
    in.read(static_cast<char*>(data), static_cast<std::streamsize>(count * 4));
    if (in.gcount() != static_cast<std::streamsize>(count * 4)) throw Error(source + ": replay buffer is truncated");
  };
  read(observations_.data(), rows * n);
  read(next_observations_.data(), rows * n);
  read(actions_.data(), n);
  read(rewards_.data(), n);
  read(terminated_.data(), n);
  size_ = size;
  next_ = next;
}

}  // namespace rdsim
