#include "rdsim/vecenv/vec_env.hpp"

#include <algorithm>
#include <exception>

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
  if (n != static_cast<std::uint64_t>(space.value_count()))
    throw Error(source + ": checkpoint holds an observation of another shape than the env's (damaged file?)");
  o.values.resize(static_cast<Eigen::Index>(n));
  read_bytes(in, o.values.data(), n * 4, source);
  if (!o.values.allFinite()) throw Error(source + ": checkpoint holds an observation that is not finite (damaged file?)");
  const std::string pixels = read_string(in, source);
  if (pixels.size() != static_cast<std::size_t>(space.byte_count()))
    throw Error(source + ": checkpoint holds an observation of another shape than the env's (damaged file?)");
  o.pixels.assign(pixels.begin(), pixels.end());
  return o;
}

std::vector<std::unique_ptr<Env>> checked(std::vector<std::unique_ptr<Env>> envs) {
  if (envs.empty()) throw Error("VecEnv needs at least one env");
  return envs;
}

int worker_count(int num_threads, std::size_t envs) { return std::clamp(num_threads, 1, static_cast<int>(envs)); }

}  // namespace

EnvWorkers auto_env_workers(const EnvConfig& env) {
  const bool cpu_pixels = env.observation == ObservationMode::RawPixels && env.renderer == "osmesa";
  return cpu_pixels ? EnvWorkers::processes : EnvWorkers::threads;
}

VecEnv::VecEnv(std::vector<std::unique_ptr<Env>> envs, std::uint64_t seed, int stats_window, int num_threads,
               EnvWorkers workers)
    : envs_(checked(std::move(envs))),
      local_(static_cast<int>(envs_.size())),
      pool_(workers == EnvWorkers::threads ? worker_count(num_threads, envs_.size()) : 1),
      tracker_(static_cast<int>(envs_.size()), stats_window),
      seed_(seed),
      start_(std::chrono::steady_clock::now()) {
  batch_.resize(spec().observation, size());
  results_.resize(envs_.size());
  begun_.assign(envs_.size(), Begun{});
  next_env_ = std::make_unique<NextEnv[]>(static_cast<std::size_t>(pool_.size()));
  all_active_.assign(envs_.size(), true);
  set_groups(1);
  const int blocks = worker_count(num_threads, envs_.size());
  if (workers == EnvWorkers::processes && blocks > 1) {
    // The same split as the threads': block w is envs [w n / T, (w + 1) n / T).
    const int n = size();
    local_ = n / blocks;
    for (int w = 1; w < blocks; ++w) {
      const int first = w * n / blocks, end = (w + 1) * n / blocks;
      std::vector<std::unique_ptr<Env>> block;
      for (int i = first; i < end; ++i) block.push_back(std::move(envs_[static_cast<std::size_t>(i)]));
      processes_.push_back(std::make_unique<EnvProcess>(std::move(block), spec(), first));
      process_first_.push_back(first);
    }
  }
  // The first reset on the owning worker too: a pixel env's renderer binds its context there.
  reset_all(seed);
}

VecEnv::~VecEnv() {
  stop_pipeline();  // a caller that left groups in flight (an error): they finish first
  for_each_env([&](int i) { envs_[static_cast<std::size_t>(i)].reset(); });
}

template <class Fn>
void VecEnv::for_each_block(Fn fn) {
  const int n = local_, workers = pool_.size();
  // Worker w owns envs [w n / T, (w + 1) n / T): the same ones every step.
  pool_.run([&](int w) { fn(w * n / workers, (w + 1) * n / workers); });
}

template <class Fn>
void VecEnv::for_each_env(Fn fn) {
  for_each_block([&](int first, int end) {
    for (int i = first; i < end; ++i) fn(i);
  });
}

template <class Local>
void VecEnv::alongside_processes(Local local) {
  std::exception_ptr error;
  try {
    local();
  } catch (...) {
    error = std::current_exception();
  }
  for (auto& p : processes_) {
    try {
      p->finish();
    } catch (...) {
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

void VecEnv::reset_all(std::uint64_t seed) {
  for (std::size_t p = 0; p < processes_.size(); ++p) {
    std::vector<std::uint64_t> seeds;
    for (int j = 0; j < processes_[p]->size(); ++j) seeds.push_back(env_seed(seed, process_first_[p] + j));
    processes_[p]->start_reset(seeds);
  }
  alongside_processes([&] {
    for_each_env([&](int i) { envs_[static_cast<std::size_t>(i)]->reset_into(batch_.column(i), env_seed(seed, i)); });
  });
  for (std::size_t p = 0; p < processes_.size(); ++p)
    for (int j = 0; j < processes_[p]->size(); ++j) processes_[p]->copy_observation(j, batch_.column(process_first_[p] + j));
}

void VecEnv::reset(std::uint64_t seed) {
  require_idle("reset");
  reset_all(seed);
  tracker_.forget_running();
}

Env& VecEnv::env(int i) {
  Env* e = envs_[static_cast<std::size_t>(i)].get();
  if (!e) throw Error("VecEnv::env(" + std::to_string(i) + "): the env lives in a worker process");
  return *e;
}

Observation VecEnv::observation(int i) const {
  Observation o;
  batch_.copy_to(i, o);
  return o;
}

double VecEnv::wall_time() const {
  return wall_offset_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

// On the worker that owns envs [first, end): touches only those envs, their columns and results.
// Envs that split a step (Env::begin_step: remote envs) all send theirs before any is finished, so
// their round trips overlap; the others step in env order as always. After an error no further
// step starts, but the ones already begun are finished (each remote env stays in step with its
// server) before the first error goes up.
void VecEnv::step_block(int first, int end, const std::vector<Action>& actions, const std::vector<bool>& active) {
  std::exception_ptr error;
  for (int i = first; i < end; ++i) {
    const auto k = static_cast<std::size_t>(i);
    begun_[k].value = false;
    if (!active[k] || error) continue;
    try {
      begun_[k].value = envs_[k]->begin_step(actions[k]);
    } catch (...) {
      error = std::current_exception();
    }
  }
  for (int i = first; i < end; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!active[k]) {
      results_[k] = EnvStep{};
      continue;
    }
    if (error && !begun_[k].value) continue;
    try {
      Env& env = *envs_[k];
      finish_env(i, begun_[k].value ? env.finish_step(batch_.column(i)) : env.step_into(actions[k], batch_.column(i)));
    } catch (...) {
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

// Env i's step outcome into its result; an episode that ended is reset (its final observation kept).
void VecEnv::finish_env(int i, const StepOutcome& o) {
  EnvStep& s = results_[static_cast<std::size_t>(i)];
  s.reward = o.reward;
  s.terminated = o.terminated;
  s.truncated = o.truncated;
  s.info = o.info;
  if (s.done()) {
    batch_.copy_to(i, s.final_observation);
    envs_[static_cast<std::size_t>(i)]->reset_into(batch_.column(i));
  }
}

const std::vector<EnvStep>& VecEnv::step(const std::vector<Action>& actions) {
  return step(actions, all_active_);
}

const std::vector<EnvStep>& VecEnv::step(const std::vector<Action>& actions, const std::vector<bool>& active) {
  if (actions.size() != envs_.size() || active.size() != envs_.size())
    throw Error("VecEnv::step: one action and one active flag per env expected");
  require_idle("step");
  for (std::size_t i = 0; i < envs_.size(); ++i) timesteps_ += active[i] ? 1 : 0;
  dispatch(actions, active);
  record(0, size(), active, timesteps_);
  return results_;
}

bool VecEnv::overlaps() const {
  const auto movable = [](const std::unique_ptr<Env>& e) { return e->steps_on_any_thread(); };
  return processes_.empty() && pool_.size() > 1 && std::all_of(envs_.begin(), envs_.end(), movable);
}

void VecEnv::dispatch(const std::vector<Action>& actions, const std::vector<bool>& active) {
  if (overlaps()) {
    step_shared(actions, active);
  } else if (processes_.empty()) {
    // The workers only read `active` and write their own envs' results.
    for_each_block([&](int first, int end) { step_block(first, end, actions, active); });
  } else {
    step_with_processes(actions, active);
  }
}

void VecEnv::record(int first, int end, const std::vector<bool>& active, long long timestep) {
  double now = -1.0;  // read the clock only when an episode ended (it costs as much as a cartpole step)
  for (int i = first; i < end; ++i) {
    if (!active[static_cast<std::size_t>(i)]) continue;
    const EnvStep& s = results_[static_cast<std::size_t>(i)];
    if (s.done() && now < 0.0) now = wall_time();
    tracker_.on_step(i, s.reward, s.info, s.done(), timestep, now);
  }
}

// Why: a worker whose envs finished early would otherwise wait at the end of every batch step for
// the slowest block (an episode's reset, a step with contacts); taking the other blocks' unstarted
// envs from the front keeps most envs on their own worker's core. Each env is still stepped once,
// into its own column and result, so the results do not depend on who stepped it.
void VecEnv::step_shared(const std::vector<Action>& actions, const std::vector<bool>& active) {
  const int n = local_, workers = pool_.size();
  for (int w = 0; w < workers; ++w) next_env_[static_cast<std::size_t>(w)].index.store(w * n / workers, std::memory_order_relaxed);
  pool_.run([&](int w) {
    for (int k = 0; k < workers; ++k) {
      const int block = (w + k) % workers, end = (block + 1) * n / workers;
      std::atomic<int>& next = next_env_[static_cast<std::size_t>(block)].index;
      for (int i; (i = next.fetch_add(1, std::memory_order_relaxed)) < end;) step_block(i, i + 1, actions, active);
    }
  });
}

void VecEnv::step_with_processes(const std::vector<Action>& actions, const std::vector<bool>& active) {
  for (auto& p : processes_) p->start_step(actions, active);
  alongside_processes([&] { step_block(0, local_, actions, active); });
  for (std::size_t p = 0; p < processes_.size(); ++p) {
    EnvProcess& block = *processes_[p];
    for (int j = 0; j < block.size(); ++j) {
      const int i = process_first_[p] + j;
      EnvStep& s = results_[static_cast<std::size_t>(i)];
      if (!active[static_cast<std::size_t>(i)]) {
        s = EnvStep{};
        continue;
      }
      const StepOutcome o = block.outcome(j);
      s.reward = o.reward;
      s.terminated = o.terminated;
      s.truncated = o.truncated;
      s.info = o.info;
      block.copy_observation(j, batch_.column(i));
      if (s.done()) block.copy_final_observation(j, s.final_observation);
    }
  }
}

// Every env's EnvState::save_state(), or nullopt for an env without one.
std::vector<std::optional<std::string>> VecEnv::env_states() const {
  std::vector<std::optional<std::string>> states(envs_.size());
  for (int i = 0; i < local_; ++i)
    if (const auto* state = dynamic_cast<const EnvState*>(envs_[static_cast<std::size_t>(i)].get()))
      states[static_cast<std::size_t>(i)] = state->save_state();
  for (std::size_t p = 0; p < processes_.size(); ++p) {
    auto block = processes_[p]->save_states();
    std::move(block.begin(), block.end(), states.begin() + process_first_[p]);
  }
  return states;
}

void VecEnv::save(std::ostream& out) const {
  require_idle("save");
  write_u64(out, static_cast<std::uint64_t>(timesteps_));
  write_f64(out, wall_time());
  const auto states = env_states();
  const bool stateful = std::all_of(states.begin(), states.end(), [](const auto& s) { return s.has_value(); });
  write_u32(out, stateful ? 1 : 0);
  if (stateful) {
    Observation o;
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      write_string(out, *states[i]);
      batch_.copy_to(static_cast<int>(i), o);
      write_observation(out, o);
    }
  }
  tracker_.save(out);
}

void VecEnv::drop_caches() {
  require_idle("drop_caches");
  for (auto& p : processes_) p->start_drop_caches();
  // On each env's own worker, like every other call into an env.
  alongside_processes([&] {
    for_each_env([&](int i) {
      if (auto* caches = dynamic_cast<EnvCaches*>(envs_[static_cast<std::size_t>(i)].get())) caches->drop_caches();
    });
  });
}

bool VecEnv::load(std::istream& in, const std::string& source) {
  require_idle("load");
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
    std::vector<std::string> states;
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      states.push_back(read_string(in, source));
      batch_.assign(static_cast<int>(i), read_observation(in, spec().observation, source));
    }
    for (int i = 0; i < local_; ++i) {
      auto* state = dynamic_cast<EnvState*>(envs_[static_cast<std::size_t>(i)].get());
      if (!state) throw Error(source + ": checkpoint holds env states this env cannot load");
      state->load_state(states[static_cast<std::size_t>(i)], source);
    }
    for (std::size_t p = 0; p < processes_.size(); ++p) {
      const auto first = states.begin() + process_first_[p];
      processes_[p]->load_states(std::vector<std::string>(first, first + processes_[p]->size()), source);
    }
  }
  tracker_.load(in, source);
  if (!stateful) {
    // Fresh episodes from seeds that differ from the run's first ones.
    reset_all(seed_ ^ static_cast<std::uint64_t>(timesteps_));
    tracker_.forget_running();
  }
  return stateful;
}

}  // namespace rdsim
