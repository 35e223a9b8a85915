// The env that applies a Randomization around a robot env (randomization.hpp): each step runs the
// action given action_latency steps before, and every observation gets Gaussian noise.
#include <deque>
#include <sstream>
#include <utility>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/envs/randomization.hpp"

namespace rdsim {
namespace {

class RandomizedEnv final : public Env, public EnvState {
public:
  RandomizedEnv(std::unique_ptr<Env> inner, EnvState& inner_state, const Randomization& r)
      : inner_(std::move(inner)), inner_state_(inner_state), r_(r) {
    const GoalLayout& goal = inner_->spec().goal;
    noisy_ = goal.active() ? goal.desired_offset() : inner_->spec().observation.size();
  }

  const Spec& spec() const override { return inner_->spec(); }
  Observation reset(std::optional<std::uint64_t> seed) override { return reset_through_into(*this, seed); }
  StepResult step(const Action& action) override { return step_through_into(*this, action); }

  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed) override {
    inner_->reset_into(out, seed);
    if (seed) rng_ = Rng::derive(*seed, rng_stream::randomization);
    pending_.clear();
    add_noise(out);
  }

  StepOutcome step_into(const Action& action, ObservationOut out) override {
    const StepOutcome o = inner_->step_into(delayed(action), out);
    add_noise(out);
    return o;
  }

  bool step_physics_only() override { return inner_->step_physics_only(); }
  bool steps_on_any_thread() const override { return inner_->steps_on_any_thread(); }
  bool render(Image& frame) override { return inner_->render(frame); }

  // The wrapped env's state, then the noise stream and the actions still to run.
  std::string save_state() const override {
    std::ostringstream out;
    write_string(out, inner_state_.save_state());
    write_string(out, rng_to_bytes(rng_));
    write_u32(out, static_cast<std::uint32_t>(pending_.size()));
    for (const Action& a : pending_) write_action(out, a);
    return out.str();
  }

  void load_state(const std::string& bytes, const std::string& source) override {
    std::istringstream in(bytes);
    const std::string inner = read_string(in, source);
    Rng rng = rng_from_bytes(read_string(in, source), source);
    const std::uint32_t count = read_u32(in, source);
    if (count > static_cast<std::uint32_t>(r_.action_latency))
      throw Error(source + ": randomized env state holds " + std::to_string(count) + " pending actions (latency " +
                  std::to_string(r_.action_latency) + ")");
    std::deque<Action> pending;
    for (std::uint32_t i = 0; i < count; ++i) pending.push_back(read_action(in, source));
    if (bytes_left(in) != 0) throw Error(source + ": randomized env state has unexpected trailing bytes");
    inner_state_.load_state(inner, source);
    rng_ = rng;
    pending_ = std::move(pending);
  }

  void drop_caches() override { inner_state_.drop_caches(); }

private:
  // The action this step runs: the one given action_latency steps before (the episode's first
  // action until then). `action` is checked now, not when it runs.
  Action delayed(const Action& action) {
    if (r_.action_latency == 0) return action;
    check(action);
    if (pending_.empty())
      for (int k = 0; k < r_.action_latency; ++k) pending_.push_back(action);
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

  void add_noise(ObservationOut out) {
    if (r_.observation_noise <= 0.0) return;
    for (int i = 0; i < noisy_; ++i) out.values[i] += static_cast<float>(r_.observation_noise * rng_.normal());
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
  int noisy_ = 0;  // the first values of an observation get noise (all but a desired goal)
  Rng rng_ = Rng::derive(0, rng_stream::randomization);
  std::deque<Action> pending_;  // actions given, not yet run (action_latency of them once stepping)
};

}  // namespace

std::unique_ptr<Env> randomized(std::unique_ptr<Env> env, const Randomization& r) {
  if (!r.active()) return env;
  // Every env that lists the option group can save its state (read_env_config checked the rest).
  auto* state = dynamic_cast<EnvState*>(env.get());
  RDSIM_ASSERT(state != nullptr, "a randomized env can save its state");
  RDSIM_ASSERT(r.observation_noise == 0.0 || env->spec().observation.type == ObsType::Float32,
               "observation noise on ground-truth observations");
  return std::make_unique<RandomizedEnv>(std::move(env), *state, r);
}

}  // namespace rdsim
