#pragma once
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/algorithms/episode_tracker.hpp"
#include "rdsim/core/env.hpp"

// Several instances of one environment stepped together (a plain loop, one thread), with
// automatic reset, a timestep counter and episode tracking. Every algorithm steps envs only
// through this, so timesteps, episodes.csv and progress statistics are the same for all.
namespace rdsim {

// What one env did in a VecEnv step. When the episode ended (terminated || truncated), the env
// has already been reset: VecEnv::observations() holds the new episode's first observation and
// `final_observation` the observation that ended the old one (bootstrap from its value when
// truncated && !terminated; never when terminated).
struct EnvStep {
  float reward = 0.0f;
  bool terminated = false;
  bool truncated = false;
  StepInfo info;
  Observation final_observation;  // only filled when the episode ended

  bool done() const { return terminated || truncated; }
  // True when the return must be bootstrapped from V(final_observation).
  bool bootstrap() const { return truncated && !terminated; }
};

class VecEnv {
public:
  // Env i is first reset with a seed drawn from Rng::derive(seed, rng_stream::env_base + i);
  // later resets continue that env's own stream. All envs must share one Spec.
  VecEnv(std::vector<std::unique_ptr<Env>> envs, std::uint64_t seed, int stats_window = 20);

  int size() const { return static_cast<int>(envs_.size()); }
  const Spec& spec() const { return envs_.front()->spec(); }
  Env& env(int i) { return *envs_[static_cast<std::size_t>(i)]; }

  // The current observation of every env (after any automatic reset).
  const std::vector<Observation>& observations() const { return observations_; }

  // Steps env i with actions[i] for every i; resets the envs whose episode ended.
  const std::vector<EnvStep>& step(const std::vector<Action>& actions);

  long long timesteps() const { return timesteps_; }
  EpisodeTracker& episodes() { return tracker_; }
  const EpisodeTracker& episodes() const { return tracker_; }

  // Seconds of training so far (includes the time before a resume).
  double wall_time() const;

  // Brings every env's engine caches to the state a checkpoint restores (EnvState::drop_caches).
  // The training loop calls it at every update boundary, so a resumed run matches an
  // uninterrupted one bit for bit.
  void drop_caches();

  // Checkpoint support. When every env implements EnvState, save() stores their complete state
  // and load() continues bit-identically; otherwise load() resets the envs with fresh seeds and
  // drops the episodes that were in progress (returns false in that case).
  void save(std::ostream& out) const;
  bool load(std::istream& in, const std::string& source);

private:
  std::vector<std::unique_ptr<Env>> envs_;
  std::vector<Observation> observations_;
  std::vector<EnvStep> results_;
  EpisodeTracker tracker_;
  std::uint64_t seed_;
  long long timesteps_ = 0;
  double wall_offset_ = 0.0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace rdsim
