#include "rdsim/vecenv/episode_tracker.hpp"

#include <algorithm>
#include <sstream>
#include <cmath>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

EpisodeTracker::EpisodeTracker(int num_envs, int window)
    : running_(static_cast<std::size_t>(num_envs)), window_(std::max(1, window)) {}

void EpisodeTracker::on_step(int env, double reward, const StepInfo& info, bool done, long long timesteps,
                             double wall_time) {
  Running& r = running_[static_cast<std::size_t>(env)];
  r.ret += reward;
  ++r.length;
  r.success = r.success || info.success;
  r.collision = r.collision || info.collision;
  r.out_of_bounds = r.out_of_bounds || info.out_of_bounds;
  if (!done) return;
  add_finished({0, timesteps, r.ret, r.length, r.success, r.collision, r.out_of_bounds, wall_time});
  r = Running{};
}

void EpisodeTracker::add_finished(EpisodeRecord rec) {
  rec.episode = ++episodes_;
  finished_.push_back(rec);
  recent_.push_back(rec);
  while (static_cast<int>(recent_.size()) > window_) recent_.pop_front();
}

void EpisodeTracker::forget_running() {
  for (auto& r : running_) r = Running{};
}

std::vector<EpisodeRecord> EpisodeTracker::take_finished() {
  std::vector<EpisodeRecord> out;
  out.swap(finished_);
  return out;
}

EpisodeStats EpisodeTracker::stats() const {
  EpisodeStats s;
  s.count = static_cast<int>(recent_.size());
  if (s.count == 0) return s;
  s.min_return = recent_.front().episode_return;
  s.max_return = recent_.front().episode_return;
  for (const auto& e : recent_) {
    s.mean_return += e.episode_return;
    s.mean_length += e.length;
    s.success_rate += e.success ? 1.0 : 0.0;
    s.min_return = std::min(s.min_return, e.episode_return);
    s.max_return = std::max(s.max_return, e.episode_return);
  }
  s.mean_return /= s.count;
  s.mean_length /= s.count;
  s.success_rate /= s.count;
  return s;
}

namespace {

// The episode's outcome flags in one word (bit 0 success, 1 collision, 2 out of bounds).
std::uint32_t outcome_bits(bool success, bool collision, bool out_of_bounds) {
  return (success ? 1u : 0u) | (collision ? 2u : 0u) | (out_of_bounds ? 4u : 0u);
}

void write_record(std::ostream& out, const EpisodeRecord& e) {
  write_u64(out, static_cast<std::uint64_t>(e.episode));
  write_u64(out, static_cast<std::uint64_t>(e.timesteps));
  write_f64(out, e.episode_return);
  write_u32(out, static_cast<std::uint32_t>(e.length));
  write_u32(out, outcome_bits(e.success, e.collision, e.out_of_bounds));
  write_f64(out, e.wall_time);
}

EpisodeRecord read_record(std::istream& in, const std::string& source) {
  EpisodeRecord e;
  e.episode = static_cast<long long>(read_u64(in, source));
  e.timesteps = static_cast<long long>(read_u64(in, source));
  e.episode_return = read_f64(in, source);
  e.length = static_cast<int>(read_u32(in, source));
  const std::uint32_t bits = read_u32(in, source);
  e.success = (bits & 1u) != 0;
  e.collision = (bits & 2u) != 0;
  e.out_of_bounds = (bits & 4u) != 0;
  e.wall_time = read_f64(in, source);
  if (e.episode < 0 || e.timesteps < 0 || e.length < 0 || bits > 7 || !std::isfinite(e.episode_return) ||
      !std::isfinite(e.wall_time))
    throw Error(source + ": checkpoint holds a damaged episode record");
  return e;
}

}  // namespace

std::string EpisodeTracker::encode(const std::vector<EpisodeRecord>& records) {
  std::ostringstream out;
  write_u64(out, records.size());
  for (const auto& e : records) write_record(out, e);
  return out.str();
}

std::vector<EpisodeRecord> EpisodeTracker::decode(const std::string& bytes, const std::string& source) {
  std::istringstream in(bytes);
  const std::uint64_t n = read_u64(in, source);
  if (n > bytes.size()) throw Error(source + ": damaged episode records");
  std::vector<EpisodeRecord> records;
  for (std::uint64_t i = 0; i < n; ++i) records.push_back(read_record(in, source));
  return records;
}

void EpisodeTracker::save(std::ostream& out) const {
  write_u64(out, static_cast<std::uint64_t>(episodes_));
  write_u32(out, static_cast<std::uint32_t>(running_.size()));
  for (const auto& r : running_) {
    write_f64(out, r.ret);
    write_u32(out, static_cast<std::uint32_t>(r.length));
    write_u32(out, outcome_bits(r.success, r.collision, r.out_of_bounds));
  }
  write_u32(out, static_cast<std::uint32_t>(recent_.size()));
  for (const auto& e : recent_) write_record(out, e);
  write_u32(out, static_cast<std::uint32_t>(finished_.size()));
  for (const auto& e : finished_) write_record(out, e);
}

void EpisodeTracker::load(std::istream& in, const std::string& source) {
  const auto episodes = static_cast<long long>(read_u64(in, source));
  if (episodes < 0) throw Error(source + ": checkpoint holds a damaged episode count");
  const std::uint32_t envs = read_u32(in, source);
  if (envs != running_.size()) {
    throw Error(source + ": checkpoint has " + std::to_string(envs) + " envs, the config " +
                std::to_string(running_.size()));
  }
  std::vector<Running> running(envs);
  for (auto& r : running) {
    r.ret = read_f64(in, source);
    r.length = static_cast<int>(read_u32(in, source));
    const std::uint32_t bits = read_u32(in, source);
    if (!std::isfinite(r.ret) || r.length < 0 || bits > 7) throw Error(source + ": checkpoint holds a damaged running episode");
    r.success = (bits & 1u) != 0;
    r.collision = (bits & 2u) != 0;
    r.out_of_bounds = (bits & 4u) != 0;
  }
  std::deque<EpisodeRecord> recent;
  for (std::uint32_t n = read_u32(in, source), i = 0; i < n; ++i) recent.push_back(read_record(in, source));
  std::vector<EpisodeRecord> finished;
  for (std::uint32_t n = read_u32(in, source), i = 0; i < n; ++i) finished.push_back(read_record(in, source));
  episodes_ = episodes;
  running_ = std::move(running);
  recent_ = std::move(recent);
  while (static_cast<int>(recent_.size()) > window_) recent_.pop_front();
  finished_ = std::move(finished);
}

}  // namespace rdsim
