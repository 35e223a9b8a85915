// Episodes that start from the demonstrations' states (demonstration_starts.hpp): where they start,
// that the rest of the episode follows the env, the draws' determinism and saved state, the errors,
// and start_redraw's new layouts around the demonstrated arm.
#include <catch2/catch.hpp>

#include <set>

#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/envs/scripted_expert.hpp"
#include "rdsim/training/demonstration_starts.hpp"

using Catch::Matchers::Contains;
using namespace rdsim;

namespace {

// The push expert's episodes from seeds 100, 101, ...: what `rdsim demos record --expert` writes.
std::shared_ptr<DemoFile> expert_demos(int episodes) {
  auto file = std::make_shared<DemoFile>();
  file->path = "push.demo";
  std::unique_ptr<Env> env = make_env(default_env_config("push"));
  std::unique_ptr<ScriptedExpert> expert = make_expert(*env);
  for (int k = 0; k < episodes; ++k) {
    DemoEpisode e;
    e.source = DemoSource::Scripted;
    e.seed = 100 + static_cast<std::uint64_t>(k);
    e.start(env->reset(e.seed));
    expert->reset();
    while (!e.ended()) {
      const Action a = expert->act();
      e.add(a, env->step(a));
    }
    file->episodes.push_back(std::move(e));
  }
  return file;
}

std::unique_ptr<Env> starting(const std::shared_ptr<const DemoFile>& demos, double fraction) {
  return start_from_demonstrations(make_env(default_env_config("push")), demos, fraction, "c.json: demonstrations.start_fraction");
}

// (episode, step) of the recorded observation equal to `obs`; (-1, -1) when none is.
std::pair<int, int> recorded_at(const DemoFile& demos, const Observation& obs) {
  for (std::size_t e = 0; e < demos.episodes.size(); ++e)
    for (std::size_t t = 0; t < demos.episodes[e].observations.size(); ++t)
      if (demos.episodes[e].observations[t].values == obs.values) return {static_cast<int>(e), static_cast<int>(t)};
  return {-1, -1};
}

}  // namespace

TEST_CASE("demonstration starts: every start is a recorded state, drawn across episodes and steps, and play goes on from it",
          "[demonstration_starts]") {
  const auto demos = expert_demos(3);
  auto env = starting(demos, 1.0);
  std::set<int> episodes, steps;
  env->reset(7);
  for (int k = 0; k < 12; ++k) {
    const Observation obs = k == 0 ? env->reset(7) : env->reset();
    const auto [e, t] = recorded_at(*demos, obs);
    REQUIRE(e >= 0);  // bit for bit the observation the demonstrator saw
    episodes.insert(e);
    steps.insert(t);
    // The next step is the env's: the demonstrated action gives the demonstrated observation.
    const DemoEpisode& ep = demos->episodes[static_cast<std::size_t>(e)];
    const StepResult r = env->step(ep.actions[static_cast<std::size_t>(t)]);
    CHECK(r.observation.values == ep.observations[static_cast<std::size_t>(t) + 1].values);
  }
  CHECK(episodes.size() == 3);
  CHECK(steps.size() > 3);
}

TEST_CASE("demonstration starts: a share of the resets, the same draws for the same seed, and saved with the env's state",
          "[demonstration_starts]") {
  const auto demos = expert_demos(2);
  auto a = starting(demos, 0.5), b = starting(demos, 0.5);
  int from_demos = 0;
  a->reset(3);
  b->reset(3);
  for (int k = 0; k < 40; ++k) {
    const Observation oa = a->reset(), ob = b->reset();
    CHECK(oa.values == ob.values);
    from_demos += recorded_at(*demos, oa).first >= 0;
  }
  CHECK(from_demos > 8);
  CHECK(from_demos < 32);

  // Saved mid-episode, loaded into another: the same steps and resets follow (caches dropped, as
  // training does at the update where it saves).
  const Action still = Action::continuous(Eigen::VectorXf::Zero(a->spec().action.dim()));
  a->step(still);
  dynamic_cast<EnvState&>(*a).drop_caches();
  auto c = starting(demos, 0.5);
  c->reset(99);
  dynamic_cast<EnvState&>(*c).load_state(dynamic_cast<EnvState&>(*a).save_state(), "state");
  CHECK(c->step(still).observation.values == a->step(still).observation.values);
  for (int k = 0; k < 6; ++k) CHECK(c->reset().values == a->reset().values);
}

TEST_CASE("demonstration starts: a file without seeds and a replay that strays are one clear error each",
          "[demonstration_starts]") {
  auto demos = expert_demos(1);
  auto unseeded = std::make_shared<DemoFile>(*demos);
  unseeded->episodes.front().seed.reset();
  CHECK_THROWS_WITH(starting(unseeded, 0.5),
                    Contains("c.json: demonstrations.start_fraction: push.demo holds no episode with a reset seed"));

  auto strayed = std::make_shared<DemoFile>(*demos);
  DemoEpisode& e = strayed->episodes.front();
  e.observations.front().values[0] += 0.01f;  // whichever step is drawn, the replay meets it first
  auto env = starting(strayed, 1.0);
  CHECK_THROWS_WITH(env->reset(1), Contains("c.json: demonstrations.start_fraction: replaying push.demo (the episode of seed 100) "
                                            "does not give its recorded observation at step 0") &&
                                       Contains("record it again"));
}

TEST_CASE("demonstration starts: an env with a shorter step limit than the demonstrations' starts early enough to take a step",
          "[demonstration_starts]") {
  const auto demos = expert_demos(2);
  EnvConfig config = default_env_config("push");
  config.max_steps = 4;
  auto env = start_from_demonstrations(make_env(config), demos, 1.0, "c.json: demonstrations.start_fraction");
  env->reset(11);
  for (int k = 0; k < 20; ++k) {
    const auto [e, t] = recorded_at(*demos, env->reset());
    REQUIRE(e >= 0);
    CHECK(t < 3);
    const StepResult r = env->step(demos->episodes[static_cast<std::size_t>(e)].actions[static_cast<std::size_t>(t)]);
    CHECK(!r.truncated);  // at most step 3 of 4
  }
}

TEST_CASE("demonstration starts: start_redraw keeps the demonstrated arm, draws a new layout, the same for the same seed and "
          "saved with the env's state",
          "[demonstration_starts]") {
  const auto demos = expert_demos(3);
  const auto redrawing = [&] {
    return start_from_demonstrations(make_env(default_env_config("push")), demos, 1.0, "c.json: demonstrations.start_fraction", 1.0);
  };
  auto a = redrawing(), b = redrawing();
  a->reset(4);
  b->reset(4);
  int new_layouts = 0;
  for (int k = 0; k < 12; ++k) {
    const Observation obs = a->reset();
    CHECK(b->reset().values == obs.values);
    // The effector's position and velocity are a recorded step's; the rest of the observation
    // (the cube unless pushed yet, the goal unless reached) is new in most starts.
    bool arm_recorded = false, same_layout = false;
    for (const DemoEpisode& e : demos->episodes)
      for (const Observation& recorded : e.observations) {
        arm_recorded = arm_recorded || recorded.values.head<6>() == obs.values.head<6>();
        same_layout = same_layout || recorded.values == obs.values;
      }
    CHECK(arm_recorded);
    new_layouts += !same_layout;
  }
  CHECK(new_layouts >= 6);

  const Action still = Action::continuous(Eigen::VectorXf::Zero(a->spec().action.dim()));
  a->step(still);
  dynamic_cast<EnvState&>(*a).drop_caches();
  auto c = redrawing();
  c->reset(99);
  dynamic_cast<EnvState&>(*c).load_state(dynamic_cast<EnvState&>(*a).save_state(), "state");
  CHECK(c->step(still).observation.values == a->step(still).observation.values);
  for (int k = 0; k < 6; ++k) CHECK(c->reset().values == a->reset().values);
}
