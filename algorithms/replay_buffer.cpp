#include "rdsim/algorithms/replay_buffer.hpp"

#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

namespace {
// One tag per storage kind: observations as floats or bytes, actions as indices or vectors.
constexpr std::uint32_t kReplayTag = 0x50524452;          // "RDRP": float observations, Discrete actions
constexpr std::uint32_t kPixelReplayTag = 0x55524452;     // "RDRU": uint8 observations, Discrete actions
constexpr std::uint32_t kBoxReplayTag = 0x42524452;       // "RDRB": float observations, Box actions
constexpr std::uint32_t kPixelBoxReplayTag = 0x43524452;  // "RDRC": uint8 observations, Box actions
// A buffer holding n-step transitions: the same tag with its last letter in lower case ("RDRp"),
// followed by the same content plus the step count of every transition.
constexpr std::uint32_t kMultiStepBit = 0x20000000;
constexpr float kPixelScale = 1.0f / 255.0f;  // as encode_observation

std::uint32_t storage_tag(bool pixels, bool box) {
  return box ? (pixels ? kPixelBoxReplayTag : kBoxReplayTag) : (pixels ? kPixelReplayTag : kReplayTag);
}
std::string storage_name(bool pixels, bool box) {
  return std::string(pixels ? "uint8 pixel" : "float") + " observations and " + (box ? "Box" : "Discrete") + " actions";
}

void check_pixels(const Observation& obs, int size) {
  if (static_cast<int>(obs.pixels.size()) != size)
    throw Error("ReplayBuffer::add: observation has " + std::to_string(obs.pixels.size()) +
                " pixel bytes, expected " + std::to_string(size));
}
}  // namespace

ReplayBuffer::ReplayBuffer(long long capacity, int observation_size, int action_dim)
    : ReplayBuffer(capacity, ObservationSpace::vector(observation_size), action_dim) {}

ReplayBuffer::ReplayBuffer(long long capacity, const ObservationSpace& space, int action_dim)
    : capacity_(capacity), observation_size_(space.size()), action_dim_(action_dim), pixels_(space.type == ObsType::UInt8) {
  if (capacity <= 0 || observation_size_ <= 0)
    throw Error("ReplayBuffer: capacity and observation size must be positive");
  if (action_dim < 0) throw Error("ReplayBuffer: action_dim must be 0 (Discrete) or positive (Box)");
  const auto n = static_cast<Eigen::Index>(capacity);
  if (pixels_) {
    pixel_obs_.resize(observation_size_, n);
    next_pixel_obs_.resize(observation_size_, n);
  } else {
    observations_.resize(observation_size_, n);
    next_observations_.resize(observation_size_, n);
  }
  if (action_dim_ > 0)
    action_values_.resize(action_dim_, n);
  else
    actions_.resize(n);
  rewards_.resize(n);
  terminated_.resize(n);
  steps_.resize(n);
}

int ReplayBuffer::largest_action() const {
  if (action_dim_ > 0 || size_ == 0) return -1;  // Box actions have no index
  return actions_.head(static_cast<Eigen::Index>(size_)).maxCoeff();
}

std::size_t ReplayBuffer::observation_bytes() const {
  return 2 * static_cast<std::size_t>(observation_size_) * static_cast<std::size_t>(capacity_) *
         (pixels_ ? 1 : sizeof(float));
}

void ReplayBuffer::store_rest(int action, float reward, bool terminated, int steps) {
  if (steps < 1) throw Error("ReplayBuffer::add: a transition spans at least 1 step, got " + std::to_string(steps));
  const auto i = static_cast<Eigen::Index>(next_);
  if (action_dim_ == 0) actions_[i] = action;
  rewards_[i] = reward;
  terminated_[i] = terminated ? 1.0f : 0.0f;
  steps_[i] = static_cast<float>(steps);
  multi_step_ = multi_step_ || steps > 1;
  next_ = (next_ + 1) % capacity_;
  if (size_ < capacity_) ++size_;
}

void ReplayBuffer::store_observations(const Eigen::Ref<const Eigen::VectorXf>& observation,
                                      const Eigen::Ref<const Eigen::VectorXf>& next_observation) {
  if (pixels_) throw Error("ReplayBuffer::add: this buffer stores pixels; pass the env's Observation");
  if (observation.size() != observation_size_ || next_observation.size() != observation_size_)
    throw Error("ReplayBuffer::add: observation size " + std::to_string(observation.size()) +
                ", expected " + std::to_string(observation_size_));
  const auto i = static_cast<Eigen::Index>(next_);
  observations_.col(i) = observation;
  next_observations_.col(i) = next_observation;
}

void ReplayBuffer::store_observations(const Observation& observation, const Observation& next_observation) {
  if (!pixels_) {
    store_observations(observation.values, next_observation.values);
    return;
  }
  check_pixels(observation, observation_size_);
  check_pixels(next_observation, observation_size_);
  const auto i = static_cast<Eigen::Index>(next_);
  pixel_obs_.col(i) = Eigen::Map<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>(observation.pixels.data(), observation_size_);
  next_pixel_obs_.col(i) =
      Eigen::Map<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>(next_observation.pixels.data(), observation_size_);
}

void ReplayBuffer::store_action(const Eigen::Ref<const Eigen::VectorXf>& action) {
  if (action_dim_ == 0) throw Error("ReplayBuffer::add: this buffer stores Discrete actions; pass an index");
  if (action.size() != action_dim_)
    throw Error("ReplayBuffer::add: action of " + std::to_string(action.size()) + " values, expected " +
                std::to_string(action_dim_));
  action_values_.col(static_cast<Eigen::Index>(next_)) = action;
}

void ReplayBuffer::add(const Eigen::Ref<const Eigen::VectorXf>& observation, int action, float reward,
                       const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated) {
  if (action_dim_ > 0) throw Error("ReplayBuffer::add: this buffer stores Box actions; pass the action's values");
  store_observations(observation, next_observation);
  store_rest(action, reward, terminated);
}

void ReplayBuffer::add(const Observation& observation, int action, float reward, const Observation& next_observation,
                       bool terminated, int steps) {
  if (action_dim_ > 0) throw Error("ReplayBuffer::add: this buffer stores Box actions; pass the action's values");
  store_observations(observation, next_observation);
  store_rest(action, reward, terminated, steps);
}

void ReplayBuffer::add(const Eigen::Ref<const Eigen::VectorXf>& observation, const Eigen::Ref<const Eigen::VectorXf>& action,
                       float reward, const Eigen::Ref<const Eigen::VectorXf>& next_observation, bool terminated) {
  store_action(action);
  store_observations(observation, next_observation);
  store_rest(0, reward, terminated);
}

void ReplayBuffer::add(const Observation& observation, const Eigen::Ref<const Eigen::VectorXf>& action, float reward,
                       const Observation& next_observation, bool terminated) {
  store_action(action);
  store_observations(observation, next_observation);
  store_rest(0, reward, terminated);
}

void ReplayBuffer::shape_batch(int batch_size, ReplayBatch& out) const {
  const Eigen::Index rows = observation_size_;
  if (out.observations.rows() != rows || out.observations.cols() != batch_size ||
      out.action_values.rows() != action_dim_) {
    out.observations.resize(rows, batch_size);
    out.next_observations.resize(rows, batch_size);
    out.actions.resize(action_dim_ > 0 ? 0 : batch_size);
    out.action_values.resize(action_dim_, action_dim_ > 0 ? batch_size : 0);
    out.rewards.resize(batch_size);
    out.terminated.resize(batch_size);
    out.steps.resize(batch_size);
  }
}

void ReplayBuffer::copy_to(long long slot, int column, ReplayBatch& out) const {
  const auto i = static_cast<Eigen::Index>(slot);
  const Eigen::Index j = column;
  if (pixels_) {
    out.observations.col(j) = pixel_obs_.col(i).cast<float>() * kPixelScale;
    out.next_observations.col(j) = next_pixel_obs_.col(i).cast<float>() * kPixelScale;
  } else {
    out.observations.col(j) = observations_.col(i);
    out.next_observations.col(j) = next_observations_.col(i);
  }
  if (action_dim_ > 0)
    out.action_values.col(j) = action_values_.col(i);
  else
    out.actions[j] = actions_[i];
  out.rewards[j] = rewards_[i];
  out.terminated[j] = terminated_[i];
  out.steps[j] = steps_[i];
}

const float* ReplayBuffer::next_observation(long long slot) const {
  return next_observations_.data() + static_cast<Eigen::Index>(slot) * observation_size_;
}

void ReplayBuffer::sample(int batch_size, Rng& rng, ReplayBatch& out) const {
  if (size_ == 0) throw Error("ReplayBuffer::sample: the buffer is empty");
  shape_batch(batch_size, out);
  sample_into(0, batch_size, rng, out);
}

void ReplayBuffer::sample_into(int first, int count, Rng& rng, ReplayBatch& out, long long* slots) const {
  if (size_ == 0) throw Error("ReplayBuffer::sample: the buffer is empty");
  for (int j = first; j < first + count; ++j) {
    const auto slot = static_cast<long long>(rng.below(static_cast<std::uint64_t>(size_)));
    copy_to(slot, j, out);
    if (slots) slots[j - first] = slot;
  }
}

void ReplayBuffer::save(std::ostream& out) const {
  const bool box = action_dim_ > 0;
  write_u32(out, storage_tag(pixels_, box) | (multi_step_ ? kMultiStepBit : 0u));
  write_u64(out, static_cast<std::uint64_t>(capacity_));
  write_u32(out, static_cast<std::uint32_t>(observation_size_));
  if (box) write_u32(out, static_cast<std::uint32_t>(action_dim_));
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
  if (box)
    write(action_values_.data(), action_dim_ * n * 4);
  else
    write(actions_.data(), n * 4);
  write(rewards_.data(), n * 4);
  write(terminated_.data(), n * 4);
  if (multi_step_) write(steps_.data(), n * 4);
}

void ReplayBuffer::load(std::istream& in, const std::string& source) {
  const std::uint32_t tagged = read_u32(in, source);
  const bool multi_step = (tagged & kMultiStepBit) != 0;
  const std::uint32_t tag = tagged & ~kMultiStepBit;
  if (tag != kReplayTag && tag != kPixelReplayTag && tag != kBoxReplayTag && tag != kPixelBoxReplayTag)
    throw Error(source + ": replay buffer not found (damaged checkpoint?)");
  const bool pixels = tag == kPixelReplayTag || tag == kPixelBoxReplayTag;
  const bool box = tag == kBoxReplayTag || tag == kPixelBoxReplayTag;
  if (pixels != pixels_ || box != (action_dim_ > 0))
    throw Error(source + ": replay buffer holds " + storage_name(pixels, box) + ", expected " +
                storage_name(pixels_, action_dim_ > 0) + " (different env observation mode or action space?)");
  const auto capacity = static_cast<long long>(read_u64(in, source));
  const auto rows = static_cast<Eigen::Index>(read_u32(in, source));
  const int action_dim = box ? static_cast<int>(read_u32(in, source)) : 0;
  if (capacity != capacity_ || rows != observation_size_ || action_dim != action_dim_)
    throw Error(source + ": replay buffer of capacity " + std::to_string(capacity) + " x " +
                std::to_string(rows) + " observation values" +
                (box ? " and " + std::to_string(action_dim) + " action values" : std::string()) + ", expected " +
                std::to_string(capacity_) + " x " + std::to_string(observation_size_) +
                (box ? " and " + std::to_string(action_dim_) : std::string()) +
                " (different buffer_size or env?)");
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
  if (box)
    read(action_values_.data(), action_dim_ * n * 4);
  else
    read(actions_.data(), n * 4);
  read(rewards_.data(), n * 4);
  read(terminated_.data(), n * 4);
  if (multi_step)
    read(steps_.data(), n * 4);
  else
    steps_.head(n).setOnes();
  const bool finite = pixels_ || (observations_.leftCols(n).allFinite() && next_observations_.leftCols(n).allFinite());
  const bool actions_ok = box ? action_values_.leftCols(n).allFinite() : (n == 0 || actions_.head(n).minCoeff() >= 0);
  if (!finite || !actions_ok || !rewards_.head(n).allFinite() ||
      !(terminated_.head(n).array() == 0.0f || terminated_.head(n).array() == 1.0f).all() ||
      !(steps_.head(n).array() >= 1.0f && steps_.head(n).array() <= 1e6f && steps_.head(n).array() == steps_.head(n).array().round()).all())
    throw Error(source + ": replay buffer holds damaged values (damaged file?)");
  multi_step_ = multi_step;
  size_ = size;
  next_ = next;
}

}  // namespace rdsim
