#include <catch2/catch.hpp>
#include <sstream>

#include "rdsim/vecenv/episode_tracker.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "../algorithms/toy_env.hpp"

namespace {
rdsim::StepInfo outcome(bool success, bool collision = false, bool out_of_bounds = false) {
  rdsim::StepInfo info;
  info.success = success;
  info.collision = collision;
  info.out_of_bounds = out_of_bounds;
  return info;
}
}  // namespace

TEST_CASE("episode tracker records finished episodes and windowed stats", "[episodes]") {
  rdsim::EpisodeTracker tracker(2, 2);
  CHECK(tracker.stats().count == 0);
  long long t = 0;
  // env 0: episodes of returns 3 (success) then 1; env 1: one episode of return 5.
  for (int k = 0; k < 3; ++k) tracker.on_step(0, 1.0, outcome(k == 1), k == 2, ++t, 0.5);
  for (int k = 0; k < 5; ++k) tracker.on_step(1, 1.0, outcome(false, k == 2), k == 4, ++t, 1.0);
  tracker.on_step(0, 1.0, outcome(false, false, true), true, ++t, 2.0);
  auto finished = tracker.take_finished();
  REQUIRE(finished.size() == 3);
  CHECK(finished[0].episode == 1);
  CHECK(finished[0].episode_return == 3.0);
  CHECK(finished[0].length == 3);
  CHECK(finished[0].success);
  CHECK_FALSE(finished[0].collision);
  CHECK_FALSE(finished[0].out_of_bounds);
  CHECK(finished[1].collision);
  CHECK_FALSE(finished[1].success);
  CHECK(finished[2].out_of_bounds);
  CHECK_FALSE(finished[2].collision);
  CHECK(finished[0].timesteps == 3);
  CHECK(finished[1].episode_return == 5.0);
  CHECK(finished[2].episode_return == 1.0);
  CHECK(tracker.take_finished().empty());
  CHECK(tracker.episodes() == 3);
  const auto s = tracker.stats();  // window 2: the episodes with returns 5 and 1
  CHECK(s.count == 2);
  CHECK(s.mean_return == 3.0);
  CHECK(s.min_return == 1.0);
  CHECK(s.max_return == 5.0);
  CHECK(s.mean_length == 3.0);
  CHECK(s.success_rate == 0.0);
}

TEST_CASE("episode tracker state round-trips", "[episodes]") {
  rdsim::EpisodeTracker a(1, 5);
  a.on_step(0, 2.0, outcome(false, true), true, 1, 0.1);
  a.on_step(0, 1.5, outcome(true, false, true), false, 2, 0.2);
  std::stringstream buf;
  a.save(buf);
  rdsim::EpisodeTracker b(1, 5);
  b.load(buf, "test");
  CHECK(b.episodes() == 1);
  a.on_step(0, 1.0, outcome(false), true, 3, 0.3);
  b.on_step(0, 1.0, outcome(false), true, 3, 0.3);
  const auto from_a = a.take_finished(), from_b = b.take_finished();
  CHECK(from_b.back().episode_return == from_a.back().episode_return);
  // Outcome flags survive the round trip: the first episode collided, the running one succeeded
  // and left the workspace.
  CHECK(from_b.front().collision);
  CHECK(from_b.back().success);
  CHECK(from_b.back().out_of_bounds);
  CHECK(b.stats().mean_return == a.stats().mean_return);
  std::stringstream wrong;
  a.save(wrong);
  rdsim::EpisodeTracker c(3, 5);
  CHECK_THROWS_AS(c.load(wrong, "test"), rdsim::Error);
}

TEST_CASE("VecEnv auto-resets, counts timesteps and keeps the final observation", "[vec_env]") {
  rdsim::VecEnv vec(toy::make_envs(3, true, 4), 7);
  CHECK(vec.size() == 3);
  const std::vector<rdsim::Action> actions(3, rdsim::Action::discrete(1));
  for (int t = 1; t <= 4; ++t) {
    const auto& steps = vec.step(actions);
    CHECK(vec.timesteps() == 3 * t);
    for (const auto& s : steps) {
      CHECK(s.truncated == (t == 4));
      CHECK(s.bootstrap() == (t == 4));
      if (t == 4) {
        // the old episode's last observation (t/length = 1) vs the new episode's first (0)
        CHECK(s.final_observation.values[1] == 1.0f);
      }
    }
  }
  for (int i = 0; i < vec.size(); ++i) CHECK(vec.observation(i).values[1] == 0.0f);
  CHECK(vec.episodes().episodes() == 3);
  const auto finished = vec.episodes().take_finished();
  REQUIRE(finished.size() == 3);
  CHECK(finished[0].length == 4);
  CHECK(finished[0].success);
  CHECK(finished[0].timesteps == 12);

  // Different envs get different seeds; the same seed gives the same observations.
  rdsim::VecEnv same(toy::make_envs(3, true, 4), 7), other(toy::make_envs(3, true, 4), 8);
  rdsim::VecEnv again(toy::make_envs(3, true, 4), 7);
  bool envs_differ = false, seeds_differ = false;
  for (int t = 0; t < 20; ++t) {
    same.step(actions);
    other.step(actions);
    again.step(actions);
    for (int i = 0; i < 3; ++i) {
      CHECK(same.observation(i).values == again.observation(i).values);
      envs_differ = envs_differ || same.observation(0).values != same.observation(i).values;
      seeds_differ = seeds_differ || same.observation(i).values != other.observation(i).values;
    }
  }
  CHECK(envs_differ);
  CHECK(seeds_differ);
}

TEST_CASE("VecEnv save/load continues identically", "[vec_env]") {
  const std::vector<rdsim::Action> actions(2, rdsim::Action::discrete(0));
  rdsim::VecEnv a(toy::make_envs(2, true, 5), 1);
  for (int t = 0; t < 7; ++t) a.step(actions);
  a.episodes().take_finished();
  std::stringstream buf;
  a.save(buf);
  rdsim::VecEnv b(toy::make_envs(2, true, 5), 99);
  CHECK(b.load(buf, "test"));
  CHECK(b.timesteps() == a.timesteps());
  for (int t = 0; t < 9; ++t) {
    a.step(actions);
    b.step(actions);
    for (int i = 0; i < 2; ++i) CHECK(a.observation(i).values == b.observation(i).values);
  }
  const auto ea = a.episodes().take_finished(), eb = b.episodes().take_finished();
  REQUIRE(ea.size() == eb.size());
  for (std::size_t k = 0; k < ea.size(); ++k) {
    CHECK(ea[k].episode == eb[k].episode);
    CHECK(ea[k].episode_return == eb[k].episode_return);
    CHECK(ea[k].length == eb[k].length);
  }
}

TEST_CASE("VecEnv steps only the active envs when asked", "[vec_env]") {
  using namespace rdsim;
  const int threads = GENERATE(1, 2);
  VecEnv vec(toy::make_envs(3, true, 4), 8, 20, threads);
  const Observation before = vec.observation(1);
  const std::vector<Action> actions(3, Action::discrete(1));
  const auto& steps = vec.step(actions, {true, false, true});
  CHECK(vec.timesteps() == 2);
  CHECK(steps[1].reward == 0.0f);
  CHECK_FALSE(steps[1].done());
  CHECK(vec.observation(1).values == before.values);  // untouched
  for (int k = 0; k < 3; ++k) vec.step(actions, {true, false, true});
  CHECK(vec.episodes().episodes() == 2);  // envs 0 and 2 finished their 4-step episodes
  vec.step(actions, {false, true, false});
  CHECK(vec.timesteps() == 9);
  CHECK_THROWS_AS(vec.step(actions, {true, true}), Error);
}
