#include "rdsim/algorithms/vec_env.hpp"

#include <algorithm>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"

namespace rdsim {
namespace {

std::uint64_t env_seed(std::uint64_t seed, int i) {
  return Rng::derive(seed, rng_stream::env_base + static_cast<std::uint64_t>(i)).next_u64();
}

void write_observation(std::ostream& out, const Observation& o) {
  write_u64(out, static_cast<std::uint64_t>(o.values.size()));
  out.write(reinterpret_cast<const char*>(o.values.data()), static_cast<std::streamsize>(o.values.size() * 4));
  write_string(out, std::string(o.pixels.begin(), o.pixels.end()));
}

// An observation as write_observation stored it, checked against the env's space.
Observation read_observation(std::istream& in, const ObservationSpace& space, const std::string& source) {
  Observation o;
  const std::uint64_t n = read_count(in, 4, source);
  const bool floats = space.type == ObsType::Float32;
  if (n != (floats ? static_cast<std::uint64_t>(space.size()) : 0))
    throw Error(source + ": checkpoint holds an observation of another shape than the env's (damaged file?)");
  o.values.resize(static_cast<Eigen::Index>(n));
  read_bytes(in, o.values.data(), n * 4, source);
  if (!o.values.allFinite()) throw Error(source + ": checkpoint holds an observation that is not finite (damaged file?)");
  const std::string pixels = read_string(in, source);
  if (pixels.size() != (floats ? 0 : static_cast<std::size_t>(space.size())))
    throw Error(source + ": checkpoint holds an observation of another shape than the env's (damaged file?)");
  o.pixels.assign(pixels.begin(), pixels.end());
  return o;
}

std::vector<std::unique_ptr<Env>> checked(std::vector<std::unique_ptr<Env>> envs) {
  if (envs.empty()) throw Error("VecEnv needs at least one env");
  return envs;
}

}  // namespace

VecEnv::VecEnv(std::vector<std::unique_ptr<Env>> envs, std::uint64_t seed, int stats_window, int num_threads)
    : envs_(checked(std::move(envs))),
      pool_(std::clamp(num_threads, 1, static_cast<int>(envs_.size()))),
      tracker_(static_cast<int>(envs_.size()), stats_window),
      seed_(seed),
      start_(std::chrono::steady_clock::now()) {
  batch_.resize(spec().observation, size());
  results_.resize(envs_.size());
  all_active_.assign(envs_.size(), true);
  // The first reset on the owning worker too: a pixel env's renderer binds its context there.
  for_each_env([&](int i) { envs_[static_cast<std::size_t>(i)]->reset_into(batch_.column(i), env_seed(seed, i)); });
}

VecEnv::~VecEnv() {
  for_each_env([&](int i) { envs_[static_cast<std::size_t>(i)].reset(); });
}

template <class Fn>
void VecEnv::for_each_env(Fn fn) {
  const int n = size(), workers = pool_.size();
  pool_.run([&](int w) {
    // Worker w owns envs [w n / T, (w + 1) n / T): the same ones every step.
    const int end = (w + 1) * n / workers;
    for (int i = w * n / workers; i < end; ++i) fn(i);
  });
}

Observation VecEnv::observation(int i) const {
  Observation o;
  batch_.copy_to(i, o);
  return o;
}

double VecEnv::wall_time() const {
  return wall_offset_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

// On env i's worker: touches only env i, its column and its result.
void VecEnv::step_env(int i, const Action& action) {
  Env& env = *envs_[static_cast<std::size_t>(i)];
  EnvStep& s = results_[static_cast<std::size_t>(i)];
  const StepOutcome o = env.step_into(action, batch_.column(i));
  s.reward = o.reward;
  s.terminated = o.terminated;
  s.truncated = o.truncated;
  s.info = o.info;
  if (s.done()) {
    batch_.copy_to(i, s.final_observation);
    env.reset_into(batch_.column(i));
  }
}

const std::vector<EnvStep>& VecEnv::step(const std::vector<Action>& actions) {
  return step(actions, all_active_);
}

const std::vector<EnvStep>& VecEnv::step(const std::vector<Action>& actions, const std::vector<bool>& active) {
  if (actions.size() != envs_.size() || active.size() != envs_.size())
    throw Error("VecEnv::step: one action and one active flag per env expected");
  for (std::size_t i = 0; i < envs_.size(); ++i) timesteps_ += active[i] ? 1 : 0;
  // The workers only read `active` and write their own envs' results.
  for_each_env([&](int i) {
    if (active[static_cast<std::size_t>(i)])
      step_env(i, actions[static_cast<std::size_t>(i)]);
    else
      results_[static_cast<std::size_t>(i)] = EnvStep{};
  });
  double now = -1.0;  // read the clock only when an episode ended (it costs as much as a cartpole step)
  for (int i = 0; i < size(); ++i) {
    if (!active[static_cast<std::size_t>(i)]) continue;
    const EnvStep& s = results_[static_cast<std::size_t>(i)];
    if (s.done() && now < 0.0) now = wall_time();
    tracker_.on_step(i, s.reward, s.info, s.done(), timesteps_, now);
  }
  return results_;
}

void VecEnv::save(std::ostream& out) const {
  write_u64(out, static_cast<std::uint64_t>(timesteps_));
  write_f64(out, wall_time());
  bool stateful = true;
  for (const auto& e : envs_) stateful = stateful && dynamic_cast<const EnvState*>(e.get()) != nullptr;
  write_u32(out, stateful ? 1 : 0);
  if (stateful) {
    Observation o;
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      write_string(out, dynamic_cast<const EnvState*>(envs_[i].get())->save_state());
      batch_.copy_to(static_cast<int>(i), o);
      write_observation(out, o);
    }
  }
  tracker_.save(out);
}

void VecEnv::drop_caches() {
  // On each env's own worker, like every other call into an env.
  for_each_env([&](int i) {
    if (auto* state = dynamic_cast<EnvState*>(envs_[static_cast<std::size_t>(i)].get())) state->drop_caches();
  });
}

bool VecEnv::load(std::istream& in, const std::string& source) {
  const std::uint64_t timesteps = read_u64(in, source);
  const double wall = read_f64(in, source);
  // Counters far beyond any run (a negative count read as unsigned, a wall time of years) mean damage.
  if (timesteps > (1ull << 50) || !(wall >= 0.0 && wall < 1e10))
    throw Error(source + ": checkpoint counters are out of range (timesteps " + std::to_string(timesteps) +
                "; damaged file?)");
  timesteps_ = static_cast<long long>(timesteps);
  wall_offset_ = wall;
  start_ = std::chrono::steady_clock::now();
  const std::uint32_t stateful_flag = read_u32(in, source);
  if (stateful_flag > 1) throw Error(source + ": checkpoint is damaged (bad env-state flag)");
  const bool stateful = stateful_flag != 0;
  if (stateful) {
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      auto* state = dynamic_cast<EnvState*>(envs_[i].get());
      if (!state) throw Error(source + ": checkpoint holds env states this env cannot load");
      state->load_state(read_string(in, source), source);
      batch_.assign(static_cast<int>(i), read_observation(in, spec().observation, source));
    }
  }
  tracker_.load(in, source);
  if (!stateful) {
    // Fresh episodes from seeds that differ from the run's first ones.
    const std::uint64_t seed = seed_ ^ static_cast<std::uint64_t>(timesteps_);
    for_each_env([&](int i) { envs_[static_cast<std::size_t>(i)]->reset_into(batch_.column(i), env_seed(seed, i)); });
    tracker_.forget_running();
  }
  return stateful;
}

}  // namespace rdsim
