// The env that applies a Randomization's per-step part around a robot env (randomization.hpp): each
// step runs the action given action_latency steps before, every observation gets Gaussian noise,
// and with observe_latency the actions still to run join the observation.
#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>
#include <utility>
#include <vector>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/core/suggest.hpp"
#include "rdsim/envs/randomization.hpp"

namespace rdsim {
namespace {

// The noise's standard deviation for each value of `spec`'s observation: observation_noise, but
// the values of the parts observation_noise_parts names get theirs, and a goal env's desired goal none.
std::vector<double> noise_levels(const Spec& spec, const Randomization& r) {
  const ObservationSpace& obs = spec.observation;
  std::vector<double> noise(static_cast<size_t>(obs.size()), r.observation_noise);
  if (spec.goal.active())
    std::fill(noise.begin() + spec.goal.desired_offset(), noise.end(), 0.0);
  const std::string key = spec.env_name + ": env.randomize.observation_noise_parts: ";
  for (const auto& [name, level] : r.observation_noise_parts) {
    if (obs.parts.empty()) throw Error(key + spec.env_name + "'s observation has no named parts");
    const auto [at, size] = obs.part(name);
    if (at < 0) {
      std::vector<std::string> names;
      for (const ObservationPart& p : obs.parts) names.push_back(p.name);
      throw Error(key + "\"" + name + "\" is not a part of " + spec.env_name + "'s observation" +
                  did_you_mean(name, names) + " (its parts: " + obs.part_names() + ")");
    }
    if (spec.goal.active() && at == spec.goal.desired_offset())
      throw Error(key + "desired_goal is the task's goal, not a reading: it stays exact");
    std::fill_n(noise.begin() + at, size, level);
  }
  return noise;
}

class RandomizedEnv final : public Env, public EnvState {
public:
  RandomizedEnv(std::unique_ptr<Env> inner, EnvState& inner_state, const Randomization& r)
      : inner_(std::move(inner)), inner_state_(inner_state), r_(r), spec_(inner_->spec()) {
    if (r.noisy()) noise_ = noise_levels(spec_, r);
    if (r.observe_latency) add_queue_to_spec();
  }

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed) override { return reset_through_into(*this, seed); }
  StepResult step(const Action& action) override { return step_through_into(*this, action); }

  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed) override {
    inner_->reset_into(inner_out(out), seed);
    if (seed) rng_ = Rng::derive(*seed, rng_stream::randomization);
    latency_ = r_.random_latency ? static_cast<int>(rng_.below(static_cast<std::uint64_t>(r_.action_latency) + 1))
                                 : r_.action_latency;
    pending_.clear();
    finish(out);
  }

  StepOutcome step_into(const Action& action, ObservationOut out) override {
    const StepOutcome o = inner_->step_into(delayed(action), inner_out(out));
    finish(out);
    return o;
  }

  bool step_physics_only() override { return inner_->step_physics_only(); }
  bool steps_on_any_thread() const override { return inner_->steps_on_any_thread(); }
  bool render(Image& frame) override { return inner_->render(frame); }

  // The wrapped env's state, then the noise stream, the episode's latency and the actions still to run.
  std::string save_state() const override {
    std::ostringstream out;
    write_string(out, inner_state_.save_state());
    write_string(out, rng_to_bytes(rng_));
    write_u32(out, static_cast<std::uint32_t>(latency_));
    write_u32(out, static_cast<std::uint32_t>(pending_.size()));
    for (const Action& a : pending_) write_action(out, a);
    return out.str();
  }

  void load_state(const std::string& bytes, const std::string& source) override {
    std::istringstream in(bytes);
    const std::string inner = read_string(in, source);
    Rng rng = rng_from_bytes(read_string(in, source), source);
    const std::uint32_t latency = read_u32(in, source);
    if (latency > static_cast<std::uint32_t>(r_.action_latency) || (!r_.random_latency && latency != static_cast<std::uint32_t>(r_.action_latency)))
      throw Error(source + ": randomized env state has a latency of " + std::to_string(latency) + " steps (config: " +
                  std::to_string(r_.action_latency) + ")");
    const std::uint32_t count = read_u32(in, source);
    if (count > latency)
      throw Error(source + ": randomized env state holds " + std::to_string(count) + " pending actions (latency " +
                  std::to_string(latency) + ")");
    std::deque<Action> pending;
    for (std::uint32_t i = 0; i < count; ++i) pending.push_back(read_action(in, source));
    if (bytes_left(in) != 0) throw Error(source + ": randomized env state has unexpected trailing bytes");
    inner_state_.load_state(inner, source);
    rng_ = rng;
    latency_ = static_cast<int>(latency);
    pending_ = std::move(pending);
  }

  void drop_caches() override { inner_state_.drop_caches(); }

private:
  // The action this step runs: the one given latency_ steps before (the episode's first action
  // until then). `action` is checked now, not when it runs.
  Action delayed(const Action& action) {
    if (latency_ == 0) return action;
    check(action);
    if (pending_.empty())
      for (int k = 0; k < latency_; ++k) pending_.push_back(action);
    pending_.push_back(action);
    Action run = std::move(pending_.front());
    pending_.pop_front();
    return run;
  }

  void check(const Action& a) const {
    const ActionSpace& space = inner_->spec().action;
    if (space.discrete ? (a.index < 0 || a.index >= space.n) : a.values.size() != space.dim())
      throw Error(spec().env_name + ": action: expected " +
                  (space.discrete ? "an index in [0, " + std::to_string(space.n) + ")"
                                  : std::to_string(space.dim()) + " values"));
  }

  // Where the wrapped env writes: `out` itself, or the scratch the queue is added to.
  ObservationOut inner_out(ObservationOut out) {
    if (queue_ == 0) return out;
    return ObservationOut{.values = scratch_.data()};
  }

  // The noise, then (observe_latency) the wrapped env's values around the queue into `out`.
  void finish(ObservationOut out) {
    float* values = queue_ == 0 ? out.values : scratch_.data();
    for (size_t i = 0; i < noise_.size(); ++i)
      if (noise_[i] > 0.0) values[i] += static_cast<float>(noise_[i] * rng_.normal());
    if (queue_ == 0) return;
    const int inner_size = static_cast<int>(scratch_.size());
    std::copy_n(scratch_.data(), split_, out.values);
    float* q = out.values + split_;
    std::fill_n(q, queue_, 0.0f);
    const ActionSpace& space = inner_->spec().action;
    const int per_action = queue_ / r_.queue_slots();
    for (const Action& a : pending_) {
      if (space.discrete)
        q[a.index] = 1.0f;
      else
        for (int k = 0; k < per_action; ++k)  // as the envs read them: clipped, non-finite values as 0
          q[k] = std::isfinite(a.values[k]) ? std::clamp(a.values[k], space.low[k], space.high[k]) : 0.0f;
      q += per_action;
    }
    std::copy(scratch_.data() + split_, scratch_.data() + inner_size, out.values + split_ + queue_);
  }

  // observe_latency: queue_slots() actions' values (Discrete: one-hot) after the env's own values.
  void add_queue_to_spec() {
    const ActionSpace& action = spec_.action;
    const int per_action = action.discrete ? action.n : action.dim();
    queue_ = r_.queue_slots() * per_action;
    ObservationSpace& obs = spec_.observation;
    const int inner_size = obs.size();
    split_ = spec_.goal.active() ? spec_.goal.observation : inner_size;
    scratch_.resize(static_cast<size_t>(inner_size));
    Eigen::VectorXf low(inner_size + queue_), high(inner_size + queue_);
    for (int k = 0; k < r_.queue_slots(); ++k) {
      const Eigen::Index at = split_ + k * per_action;
      low.segment(at, per_action) = action.discrete ? Eigen::VectorXf::Zero(per_action) : action.low;
      high.segment(at, per_action) = action.discrete ? Eigen::VectorXf::Ones(per_action) : action.high;
    }
    low.head(split_) = obs.low.head(split_);
    high.head(split_) = obs.high.head(split_);
    low.tail(inner_size - split_) = obs.low.tail(inner_size - split_);
    high.tail(inner_size - split_) = obs.high.tail(inner_size - split_);
    if (!obs.parts.empty()) {  // the queue's part goes where its values go: before a goal env's goals
      auto at = obs.parts.end();
      if (spec_.goal.active()) at -= 2;
      obs.parts.insert(at, ObservationPart{"pending_actions", queue_});
    }
    obs.shape = {inner_size + queue_};
    obs.low = low;
    obs.high = high;
    if (spec_.goal.active()) spec_.goal.observation += queue_;
  }

  void write_action(std::ostream& out, const Action& a) const {
    if (inner_->spec().action.discrete) {
      write_u32(out, static_cast<std::uint32_t>(a.index));
      return;
    }
    for (Eigen::Index k = 0; k < a.values.size(); ++k) write_f32(out, a.values[k]);
  }

  Action read_action(std::istream& in, const std::string& source) const {
    const ActionSpace& space = inner_->spec().action;
    Action a;
    if (space.discrete) {
      a.index = static_cast<int>(read_u32(in, source));
      if (a.index < 0 || a.index >= space.n) throw Error(source + ": randomized env state holds an action out of range");
      return a;
    }
    a.values.resize(space.dim());
    for (int k = 0; k < space.dim(); ++k) a.values[k] = read_f32(in, source);
    if (!a.values.allFinite()) throw Error(source + ": randomized env state holds an action that is not finite");
    return a;
  }

  std::unique_ptr<Env> inner_;
  EnvState& inner_state_;
  Randomization r_;
  Spec spec_;      // the wrapped env's, with the queue when observe_latency
  std::vector<double> noise_;  // standard deviation per value of the wrapped env's observation (empty: none)
  int queue_ = 0;  // values of the queued actions in the observation (observe_latency)
  int split_ = 0;  // where they go: after the wrapped env's own values, before its goals
  std::vector<float> scratch_;  // the wrapped env's observation (observe_latency)
  Rng rng_ = Rng::derive(0, rng_stream::randomization);
  int latency_ = 0;             // this episode's (action_latency, or drawn with random_latency)
  std::deque<Action> pending_;  // actions given, not yet run (latency_ of them once stepping)
};

}  // namespace

std::unique_ptr<Env> randomized(std::unique_ptr<Env> env, const Randomization& r) {
  if (!r.per_step()) return env;
  // Every env that lists the option group can save its state (read_env_config checked the rest).
  auto* state = dynamic_cast<EnvState*>(env.get());
  RDSIM_ASSERT(state != nullptr, "a randomized env can save its state");
  RDSIM_ASSERT(!r.noisy() || env->spec().observation.type == ObsType::Float32,
               "observation noise on ground-truth observations");
  return std::make_unique<RandomizedEnv>(std::move(env), *state, r);
}

}  // namespace rdsim
