// The two ways to drive an env (core/env.hpp): reset_into/step_into write into caller memory and
// must give exactly what reset/step return, for every registered env, ground truth and pixels.
#include <catch2/catch.hpp>

#include "rdsim/core/rng.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;

namespace {

Action random_action(const ActionSpace& space, Rng& rng) {
  if (space.discrete) return Action::discrete(static_cast<int>(rng.below(static_cast<std::uint64_t>(space.n))));
  Eigen::VectorXf v(space.low.size());
  for (int i = 0; i < v.size(); ++i) v[i] = static_cast<float>(rng.uniform(space.low[i], space.high[i]));
  return Action::continuous(v);
}

bool same(const Observation& a, const Observation& b) { return a.values == b.values && a.pixels == b.pixels; }

}  // namespace

TEST_CASE("every env's step_into/reset_into match step/reset exactly", "[envs][into]") {
  for (const EnvEntry& entry : env_registry()) {
    for (bool pixels : {false, true}) {
      if (pixels && !entry.supports_pixels) continue;
      INFO(entry.name << (pixels ? " raw_pixels" : " ground_truth"));
      EnvConfig config = entry.defaults();
      if (auto* reach = config.find<ReachOptions>()) reach->random_target = true;
      if (pixels) {
        config.observation = ObservationMode::RawPixels;
        config.image_width = config.image_height = 24;
      }
      auto plain = entry.make(config), into = entry.make(config);
      const ObservationSpace& space = plain->spec().observation;
      Observation buffer = make_observation(space);
      Rng rng(3);
      CHECK(same(plain->reset(7), (into->reset_into(observation_out(buffer), 7), buffer)));
      for (int t = 0; t < 120; ++t) {
        const Action a = random_action(plain->spec().action, rng);
        const StepResult r = plain->step(a);
        const StepOutcome o = into->step_into(a, observation_out(buffer));
        REQUIRE(same(r.observation, buffer));
        CHECK(r.reward == o.reward);
        CHECK(r.terminated == o.terminated);
        CHECK(r.truncated == o.truncated);
        CHECK(r.info.success == o.info.success);
        CHECK(r.info.distance == o.info.distance);
        if (r.terminated || r.truncated) {
          CHECK(same(plain->reset(), (into->reset_into(observation_out(buffer)), buffer)));
        }
      }
    }
  }
}

TEST_CASE("copy_observation rejects an observation of the wrong size or type", "[envs][into]") {
  ObservationSpace space;
  space.shape = {3};
  Observation obs;
  obs.values = Eigen::VectorXf::Ones(2);
  float out[3];
  CHECK_THROWS(copy_observation(obs, space, {out, nullptr}));
  obs.values = Eigen::VectorXf::Ones(3);
  copy_observation(obs, space, {out, nullptr});
  CHECK(out[2] == 1.0f);
  CHECK_THROWS(copy_observation(obs, space, {nullptr, nullptr}));
}
