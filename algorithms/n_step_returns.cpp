#include "rdsim/algorithms/n_step_returns.hpp"

#include <cmath>
#include <istream>
#include <ostream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

NStepReturns::NStepReturns(int n, double gamma, const ObservationSpace& space) : n_(n), gamma_(gamma), space_(space) {
  if (n < 1) throw Error("NStepReturns: n must be at least 1, got " + std::to_string(n));
}

void NStepReturns::emit_front(std::deque<Pending>& queue, const Observation& next_observation, bool terminated,
                              ReplayBuffer& buffer) const {
  // Accumulated in double: a window of one step stores its reward unchanged (0 + 1 * r).
  double sum = 0.0, discount = 1.0;
  for (const Pending& p : queue) {
    sum += discount * static_cast<double>(p.reward);
    discount *= gamma_;
  }
  const Pending& first = queue.front();
  buffer.add(first.observation, first.action, static_cast<float>(sum), next_observation, terminated,
             static_cast<int>(queue.size()));
  queue.pop_front();
}

void NStepReturns::add(int env, const Observation& observation, int action, float reward,
                       const Observation& next_observation, bool terminated, bool done, ReplayBuffer& buffer) {
  if (n_ == 1) {  // nothing waits: straight into the buffer, no copy of the observation
    buffer.add(observation, action, reward, next_observation, terminated);
    return;
  }
  if (env < 0) throw Error("NStepReturns::add: negative env index");
  if (static_cast<std::size_t>(env) >= pending_.size()) pending_.resize(static_cast<std::size_t>(env) + 1);
  std::deque<Pending>& queue = pending_[static_cast<std::size_t>(env)];
  queue.push_back({observation, action, reward});
  if (done) {
    while (!queue.empty()) emit_front(queue, next_observation, terminated, buffer);
  } else if (static_cast<int>(queue.size()) == n_) {
    emit_front(queue, next_observation, false, buffer);
  }
}

namespace {
constexpr std::uint32_t kTag = 0x534e4452;  // "RDNS"

void write_observation(std::ostream& out, const Observation& o) {
  write_string(out, std::string(reinterpret_cast<const char*>(o.values.data()), o.values.size() * sizeof(float)));
  write_string(out, std::string(reinterpret_cast<const char*>(o.pixels.data()), o.pixels.size()));
}

Observation read_observation(std::istream& in, const std::string& source, const ObservationSpace& space) {
  const std::string values = read_string(in, source), pixels = read_string(in, source);
  const auto size = static_cast<std::size_t>(space.size());
  const bool ok = space.type == ObsType::UInt8 ? values.empty() && pixels.size() == size
                                                : pixels.empty() && values.size() == size * sizeof(float);
  if (!ok) throw Error(source + ": damaged n-step returns state (an observation of the wrong size)");
  Observation o;
  o.values.resize(static_cast<Eigen::Index>(values.size() / sizeof(float)));
  std::copy(values.begin(), values.end(), reinterpret_cast<char*>(o.values.data()));
  o.pixels.assign(pixels.begin(), pixels.end());
  if (!o.values.allFinite()) throw Error(source + ": damaged n-step returns state (observation not finite)");
  return o;
}
}  // namespace

void NStepReturns::save(std::ostream& out) const {
  write_u32(out, kTag);
  write_u32(out, static_cast<std::uint32_t>(n_));
  write_u32(out, static_cast<std::uint32_t>(pending_.size()));
  for (const auto& queue : pending_) {
    write_u32(out, static_cast<std::uint32_t>(queue.size()));
    for (const Pending& p : queue) {
      write_observation(out, p.observation);
      write_u32(out, static_cast<std::uint32_t>(p.action));
      write_f32(out, p.reward);
    }
  }
}

void NStepReturns::load(std::istream& in, const std::string& source) {
  if (read_u32(in, source) != kTag) throw Error(source + ": n-step returns state not found (damaged checkpoint?)");
  const std::uint32_t n = read_u32(in, source), envs = read_u32(in, source);
  if (static_cast<int>(n) != n_)
    throw Error(source + ": n-step returns state of n = " + std::to_string(n) + ", expected n = " + std::to_string(n_) +
                " (a different dqn.n_step?)");
  if (envs > (1u << 20)) throw Error(source + ": damaged n-step returns state (" + std::to_string(envs) + " envs)");
  std::vector<std::deque<Pending>> loaded(envs);
  for (auto& queue : loaded) {
    const std::uint32_t count = read_u32(in, source);
    if (count >= n) throw Error(source + ": damaged n-step returns state");
    for (std::uint32_t k = 0; k < count; ++k) {
      Pending p;
      p.observation = read_observation(in, source, space_);
      p.action = static_cast<int>(read_u32(in, source));
      p.reward = read_f32(in, source);
      if (p.action < 0 || !std::isfinite(p.reward)) throw Error(source + ": damaged n-step returns state");
      queue.push_back(std::move(p));
    }
  }
  pending_ = std::move(loaded);
}

}  // namespace rdsim
