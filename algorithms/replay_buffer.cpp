#include "rdsim/algorithms/replay_buffer.hpp"

#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

namespace {
constexpr std::uint32_t kReplayTag = 0x50524452;       // "RDRP": float observations
constexpr std::uint32_t kPixelReplayTag = 0x55524452;  // "RDRU": uint8 observations
constexpr float kPixelScale = 1.0f / 255.0f;           // as encode_observation

const char* storage_name(bool pixels) { return pixels ? "uint8 pixel" : "float"; }

void check_pixels(const Observation& obs, int size) {
  if (static_cast<int>(obs.pixels.size()) != size)
    throw Error("ReplayBuffer::add: observation has " + std::to_string(obs.pixels.size()) +
                " pixel bytes, expected " + std::to_string(size));
}
}  // namespace

ReplayBuffer::ReplayBuffer(long long capacity, int observation_size)
    : ReplayBuffer(capacity, ObservationSpace{ObsType::Float32, {observation_size}, {}, {}}) {}

ReplayBuffer::ReplayBuffer(long long capacity, const ObservationSpace& space)
    : capacity_(capacity), observation_size_(space.size()), pixels_(space.type == ObsType::UInt8) {
  if (capacity <= 0 || observation_size_ <= 0)
    throw Error("ReplayBuffer: capacity and observation size must be positive");
  const auto n = static_cast<Eigen::Index>(capacity);
  if (pixels_) {
    pixel_obs_.resize(observation_size_, n);
    next_pixel_obs_.resize(observation_size_, n);
  } else {
    observations_.resize(observation_size_, n);
    next_observations_.resize(observation_size_, n);
  }
  actions_.resize(n);
  rewards_.resize(n);
  terminated_.resize(n);
}

int ReplayBuffer::largest_action() const {
  return size_ > 0 ? actions_.head(static_cast<Eigen::Index>(size_)).maxCoeff() : -1;
}

std::size_t ReplayBuffer::observation_bytes() const {
  return 2 * static_cast<std::size_t>(observation_size_) * static_cast<std::size_t>(capacity_) *
         (pixels_ ? 1 : sizeof(float));
}

void ReplayBuffer::store_rest(int action, float reward, bool terminated) {
  const auto i = static_cast<Eigen::Index>(next_);
  actions_[i] = action;
  rewards_[i] = reward;
  terminated_[i] = terminated ? 1.0f : 0.0f;
  next_ = (next_ + 1) % capacity_;
  if (size_ < capacity_) ++size_;
}

void ReplayBuffer::add(const Eigen::Ref<const Eigen::VectorXf>& observation, int action, float reward,
                       const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated) {
  if (pixels_) throw Error("ReplayBuffer::add: this buffer stores pixels; pass the env's Observation");
  if (observation.size() != observation_size_ || next_observation.size() != observation_size_)
    throw Error("ReplayBuffer::add: observation size " + std::to_string(observation.size()) +
                ", expected " + std::to_string(observation_size_));
  const auto i = static_cast<Eigen::Index>(next_);
  observations_.col(i) = observation;
  next_observations_.col(i) = next_observation;
  store_rest(action, reward, terminated);
}

void ReplayBuffer::add(const Observation& observation, int action, float reward, const Observation& next_observation,
                       bool terminated) {
  if (!pixels_) {
    add(observation.values, action, reward, next_observation.values, terminated);
    return;
  }
  check_pixels(observation, observation_size_);
  check_pixels(next_observation, observation_size_);
  const auto i = static_cast<Eigen::Index>(next_);
  pixel_obs_.col(i) = Eigen::Map<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>(observation.pixels.data(), observation_size_);
  next_pixel_obs_.col(i) =
      Eigen::Map<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>(next_observation.pixels.data(), observation_size_);
  store_rest(action, reward, terminated);
}

void ReplayBuffer::sample(int batch_size, Rng& rng, ReplayBatch& out) const {
  if (size_ == 0) throw Error("ReplayBuffer::sample: the buffer is empty");
  const Eigen::Index rows = observation_size_;
  if (out.observations.rows() != rows || out.observations.cols() != batch_size) {
    out.observations.resize(rows, batch_size);
    out.next_observations.resize(rows, batch_size);
    out.actions.resize(batch_size);
    out.rewards.resize(batch_size);
    out.terminated.resize(batch_size);
  }
  for (int j = 0; j < batch_size; ++j) {
    const auto i = static_cast<Eigen::Index>(rng.below(static_cast<std::uint64_t>(size_)));
    if (pixels_) {
      out.observations.col(j) = pixel_obs_.col(i).cast<float>() * kPixelScale;
      out.next_observations.col(j) = next_pixel_obs_.col(i).cast<float>() * kPixelScale;
    } else {
      out.observations.col(j) = observations_.col(i);
      out.next_observations.col(j) = next_observations_.col(i);
    }
    out.actions[j] = actions_[i];
    out.rewards[j] = rewards_[i];
    out.terminated[j] = terminated_[i];
  }
}

void ReplayBuffer::save(std::ostream& out) const {
  write_u32(out, pixels_ ? kPixelReplayTag : kReplayTag);
  write_u64(out, static_cast<std::uint64_t>(capacity_));
  write_u32(out, static_cast<std::uint32_t>(observation_size_));
  write_u64(out, static_cast<std::uint64_t>(size_));
  write_u64(out, static_cast<std::uint64_t>(next_));
  // Only the filled slots: a young buffer with a large capacity stays small on disk.
  const auto n = static_cast<Eigen::Index>(size_);
  const auto write = [&](const void* data, Eigen::Index bytes) {
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  };
  const Eigen::Index obs_bytes = observation_size_ * n * (pixels_ ? 1 : 4);
  write(pixels_ ? static_cast<const void*>(pixel_obs_.data()) : observations_.data(), obs_bytes);
  write(pixels_ ? static_cast<const void*>(next_pixel_obs_.data()) : next_observations_.data(), obs_bytes);
  write(actions_.data(), n * 4);
  write(rewards_.data(), n * 4);
  write(terminated_.data(), n * 4);
}

void ReplayBuffer::load(std::istream& in, const std::string& source) {
  const std::uint32_t tag = read_u32(in, source);
  if (tag != kReplayTag && tag != kPixelReplayTag)
    throw Error(source + ": replay buffer not found (damaged checkpoint?)");
  const bool pixels = tag == kPixelReplayTag;
  if (pixels != pixels_)
    throw Error(source + ": replay buffer holds " + storage_name(pixels) + " observations, expected " +
                storage_name(pixels_) + " ones (different env observation mode?)");
  const auto capacity = static_cast<long long>(read_u64(in, source));
  const auto rows = static_cast<Eigen::Index>(read_u32(in, source));
  if (capacity != capacity_ || rows != observation_size_)
    throw Error(source + ": replay buffer of capacity " + std::to_string(capacity) + " x " +
                std::to_string(rows) + " observation values, expected " + std::to_string(capacity_) +
                " x " + std::to_string(observation_size_) + " (different dqn.buffer_size or env?)");
  const auto size = static_cast<long long>(read_u64(in, source));
  const auto next = static_cast<long long>(read_u64(in, source));
  if (size < 0 || size > capacity_ || next < 0 || next >= capacity_)
    throw Error(source + ": damaged replay buffer");
  const auto n = static_cast<Eigen::Index>(size);
  const auto read = [&](void* data, Eigen::Index bytes) {
    in.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes));
    if (in.gcount() != static_cast<std::streamsize>(bytes)) throw Error(source + ": replay buffer is truncated");
  };
  const Eigen::Index obs_bytes = rows * n * (pixels_ ? 1 : 4);
  read(pixels_ ? static_cast<void*>(pixel_obs_.data()) : observations_.data(), obs_bytes);
  read(pixels_ ? static_cast<void*>(next_pixel_obs_.data()) : next_observations_.data(), obs_bytes);
  read(actions_.data(), n * 4);
  read(rewards_.data(), n * 4);
  read(terminated_.data(), n * 4);
  const bool finite = pixels_ || (observations_.leftCols(n).allFinite() && next_observations_.leftCols(n).allFinite());
  if (!finite || !rewards_.head(n).allFinite() || (n > 0 && actions_.head(n).minCoeff() < 0) ||
      !(terminated_.head(n).array() == 0.0f || terminated_.head(n).array() == 1.0f).all())
    throw Error(source + ": replay buffer holds damaged values (damaged file?)");
  size_ = size;
  next_ = next;
}

}  // namespace rdsim
