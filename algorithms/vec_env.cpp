#include "rdsim/algorithms/vec_env.hpp"

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

Observation read_observation(std::istream& in, const std::string& source) {
  Observation o;
  const std::uint64_t n = read_u64(in, source);
  if (n > (1u << 24)) throw Error(source + ": damaged observation in checkpoint");
  o.values.resize(static_cast<Eigen::Index>(n));
  in.read(reinterpret_cast<char*>(o.values.data()), static_cast<std::streamsize>(n * 4));
  if (!in) throw Error(source + ": file is truncated");
  const std::string pixels = read_string(in, source);
  o.pixels.assign(pixels.begin(), pixels.end());
  return o;
}

}  // namespace

VecEnv::VecEnv(std::vector<std::unique_ptr<Env>> envs, std::uint64_t seed, int stats_window)
    : envs_(std::move(envs)),
      tracker_(static_cast<int>(envs_.size()), stats_window),
      seed_(seed),
      start_(std::chrono::steady_clock::now()) {
  if (envs_.empty()) throw Error("VecEnv needs at least one env");
  for (int i = 0; i < size(); ++i) observations_.push_back(envs_[static_cast<std::size_t>(i)]->reset(env_seed(seed, i)));
  results_.resize(envs_.size());
  all_active_.assign(envs_.size(), true);
}

double VecEnv::wall_time() const {
  return wall_offset_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

const std::vector<EnvStep>& VecEnv::step(const std::vector<Action>& actions) {
  return step(actions, all_active_);
}

const std::vector<EnvStep>& VecEnv::step(const std::vector<Action>& actions, const std::vector<bool>& active) {
  if (actions.size() != envs_.size() || active.size() != envs_.size())
    throw Error("VecEnv::step: one action and one active flag per env expected");
  for (std::size_t i = 0; i < envs_.size(); ++i) timesteps_ += active[i] ? 1 : 0;
  const double now = wall_time();
  for (std::size_t i = 0; i < envs_.size(); ++i) {
    EnvStep& s = results_[i];
    if (!active[i]) {
      s = EnvStep{};
      continue;
    }
    StepResult r = envs_[i]->step(actions[i]);
    s.reward = r.reward;
    s.terminated = r.terminated;
    s.truncated = r.truncated;
    s.info = r.info;
    tracker_.on_step(static_cast<int>(i), r.reward, r.info, s.done(), timesteps_, now);
    if (s.done()) {
      s.final_observation = std::move(r.observation);
      observations_[i] = envs_[i]->reset();
    } else {
      observations_[i] = std::move(r.observation);
    }
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
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      write_string(out, dynamic_cast<const EnvState*>(envs_[i].get())->save_state());
      write_observation(out, observations_[i]);
    }
  }
  tracker_.save(out);
}

bool VecEnv::load(std::istream& in, const std::string& source) {
  timesteps_ = static_cast<long long>(read_u64(in, source));
  wall_offset_ = read_f64(in, source);
  start_ = std::chrono::steady_clock::now();
  const bool stateful = read_u32(in, source) != 0;
  if (stateful) {
    for (std::size_t i = 0; i < envs_.size(); ++i) {
      auto* state = dynamic_cast<EnvState*>(envs_[i].get());
      if (!state) throw Error(source + ": checkpoint holds env states this env cannot load");
      state->load_state(read_string(in, source), source);
      observations_[i] = read_observation(in, source);
    }
  }
  tracker_.load(in, source);
  if (!stateful) {
    // Fresh episodes from seeds that differ from the run's first ones.
    for (int i = 0; i < size(); ++i) {
      observations_[static_cast<std::size_t>(i)] =
          envs_[static_cast<std::size_t>(i)]->reset(env_seed(seed_ ^ static_cast<std::uint64_t>(timesteps_), i));
    }
    tracker_.forget_running();
  }
  return stateful;
}

}  // namespace rdsim
