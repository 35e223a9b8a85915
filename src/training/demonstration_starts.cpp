#include "rdsim/training/demonstration_starts.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/rng_bytes.hpp"
#include "rdsim/core/scene_redraw.hpp"

namespace rdsim {
namespace {

// A replayed observation may differ from the recorded one by float rounding at most (the same
// build replays the same bits; this leaves room for a file written through another path).
constexpr float kReplayTolerance = 1e-4f;

// How far the observation in `out` lies from `recorded` (the largest difference of one value or byte).
double replay_difference(const ObservationSpace& space, ObservationOut out, const Observation& recorded) {
  double worst = 0.0;
  if (space.type == ObsType::Float32) {
    for (Eigen::Index k = 0; k < recorded.values.size(); ++k)
      worst = std::max(worst, static_cast<double>(std::abs(out.values[k] - recorded.values[k])));
  } else {
    for (std::size_t k = 0; k < recorded.pixels.size(); ++k)
      worst = std::max(worst, std::abs(static_cast<double>(out.pixels[k]) - recorded.pixels[k]));
  }
  return worst;
}

class DemonstrationStartEnv : public Env {
public:
  DemonstrationStartEnv(std::unique_ptr<Env> inner, std::shared_ptr<const DemoFile> demos, double fraction, double redraw,
                        std::string where)
      : inner_(std::move(inner)), demos_(std::move(demos)), fraction_(fraction), redraw_(redraw), where_(std::move(where)) {
    RDSIM_ASSERT(redraw_ <= 0.0 || dynamic_cast<SceneRedraw*>(inner_.get()) != nullptr,
                 "start_redraw is checked against the env before (env_source.cpp)");
    for (std::size_t e = 0; e < demos_->episodes.size(); ++e)
      if (demos_->episodes[e].seed && demos_->episodes[e].steps() > 0) replayable_.push_back(e);
    if (replayable_.empty())
      throw Error(where_ + ": " + demos_->path +
                  " holds no episode with a reset seed to replay (scripted episodes have one: rdsim demos record "
                  "--expert; a person's need `rdsim teleop --record` with --seed)");
  }

  const Spec& spec() const override { return inner_->spec(); }
  Observation reset(std::optional<std::uint64_t> seed) override { return reset_through_into(*this, seed); }
  StepResult step(const Action& action) override { return step_through_into(*this, action); }

  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed) override {
    if (seed) rng_ = Rng::derive(*seed, rng_stream::demonstration_starts);
    if (rng_.uniform() < fraction_) {
      const DemoEpisode& e = demos_->episodes[replayable_[rng_.below(replayable_.size())]];
      // A step the env's own limit leaves at least one step after (demonstrations may have been
      // recorded with a longer env.max_steps).
      const int limit = spec().max_episode_steps;
      const int steps = limit > 0 ? std::clamp(limit - 1, 1, e.steps()) : e.steps();
      replay(e, static_cast<int>(rng_.below(static_cast<std::uint64_t>(steps))), out);
      // Drawn only with start_redraw, so that runs without it keep their draws.
      if (redraw_ > 0.0 && rng_.uniform() < redraw_) dynamic_cast<SceneRedraw&>(*inner_).redraw_unmoved(rng_, out);
      return;
    }
    inner_->reset_into(out, rng_.next_u64());
  }

  StepOutcome step_into(const Action& action, ObservationOut out) override { return inner_->step_into(action, out); }
  bool begin_step(const Action& action) override { return inner_->begin_step(action); }
  StepOutcome finish_step(ObservationOut out) override { return inner_->finish_step(out); }
  bool step_physics_only() override { return inner_->step_physics_only(); }
  bool steps_on_any_thread() const override { return inner_->steps_on_any_thread(); }
  bool render(Image& frame) override { return inner_->render(frame); }

protected:
  void forward_drop_caches() {
    if (auto* caches = dynamic_cast<EnvCaches*>(inner_.get())) caches->drop_caches();
  }
  // The wrapped env's state, then the stream.
  std::string save_wrapped() const {
    std::ostringstream out;
    write_string(out, dynamic_cast<const EnvState&>(*inner_).save_state());
    write_string(out, rng_to_bytes(rng_));
    return out.str();
  }
  void load_wrapped(const std::string& bytes, const std::string& source) {
    std::istringstream in(bytes);
    const std::string inner = read_string(in, source);
    Rng rng = rng_from_bytes(read_string(in, source), source);
    if (bytes_left(in) != 0) throw Error(source + ": demonstration-start env state has unexpected trailing bytes");
    dynamic_cast<EnvState&>(*inner_).load_state(inner, source);
    rng_ = rng;
  }

private:
  // Resets with the episode's seed and runs its first `steps` actions; the observation after them in `out`.
  void replay(const DemoEpisode& e, int steps, ObservationOut out) {
    inner_->reset_into(out, *e.seed);
    for (int t = 0;; ++t) {
      const double off = replay_difference(spec().observation, out, e.observations[static_cast<std::size_t>(t)]);
      if (!(off <= kReplayTolerance))
        throw Error(where_ + ": replaying " + demos_->path + " (the episode of seed " + std::to_string(*e.seed) +
                    ") does not give its recorded observation at step " + std::to_string(t) + " (off by " +
                    std::to_string(off) +
                    "): the file was recorded by another build of rdsim or with other env options; record it again");
      if (t == steps) return;
      const StepOutcome o = inner_->step_into(e.actions[static_cast<std::size_t>(t)], out);
      if (o.terminated || o.truncated)
        throw Error(where_ + ": replaying " + demos_->path + " (the episode of seed " + std::to_string(*e.seed) +
                    ") ends the episode at step " + std::to_string(t + 1) + " of " + std::to_string(e.steps()) +
                    ": the file was recorded by another build of rdsim or with other env options; record it again");
    }
  }

  std::unique_ptr<Env> inner_;
  std::shared_ptr<const DemoFile> demos_;
  double fraction_;
  double redraw_;  // the share of those starts whose unmoved objects are drawn again
  std::string where_;
  std::vector<std::size_t> replayable_;  // episodes with a reset seed and at least one step
  Rng rng_ = Rng::derive(0, rng_stream::demonstration_starts);
};

// Around an env without a saved state (a remote env): its caches still follow training's drops.
class DemonstrationStartCachesEnv final : public DemonstrationStartEnv, public EnvCaches {
public:
  using DemonstrationStartEnv::DemonstrationStartEnv;
  void drop_caches() override { forward_drop_caches(); }
};

class DemonstrationStartStateEnv final : public DemonstrationStartEnv, public EnvState {
public:
  using DemonstrationStartEnv::DemonstrationStartEnv;
  std::string save_state() const override { return save_wrapped(); }
  void load_state(const std::string& bytes, const std::string& source) override { load_wrapped(bytes, source); }
  void drop_caches() override { forward_drop_caches(); }
};

}  // namespace

std::unique_ptr<Env> start_from_demonstrations(std::unique_ptr<Env> env, std::shared_ptr<const DemoFile> demos,
                                               double fraction, const std::string& where, double redraw) {
  if (dynamic_cast<EnvState*>(env.get()))
    return std::make_unique<DemonstrationStartStateEnv>(std::move(env), std::move(demos), fraction, redraw, where);
  return std::make_unique<DemonstrationStartCachesEnv>(std::move(env), std::move(demos), fraction, redraw, where);
}

}  // namespace rdsim
