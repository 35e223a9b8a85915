// Hindsight experience replay (algorithms/hindsight_replay.cpp): episodes of interleaved envs kept
// apart, goals relabelled from the right episode with the reward and termination the goal layout
// gives, cut episodes never relabelled, checkpoints exact.
#include <catch2/catch.hpp>

#include <set>
#include <sstream>

#include "rdsim/algorithms/hindsight_replay.hpp"
#include "rdsim/core/error.hpp"

using namespace rdsim;

namespace {

// One goal point, no other observation: [achieved (3) | desired (3)].
GoalLayout point_goal() { return GoalLayout{.observation = 0, .points = 1, .distance_threshold = 0.05f, .reward = GoalReward::Sparse}; }

// The observation of env `env` at step `t`: achieved = (env, t, 0), desired = (9, 9, 9) (never reached).
Eigen::VectorXf obs(int env, int t) {
  Eigen::VectorXf o(6);
  o << static_cast<float>(env), static_cast<float>(t), 0.0f, 9.0f, 9.0f, 9.0f;
  return o;
}

// `steps` VecEnv steps of `envs` envs whose episodes all last `length` steps, into buffer and HER.
void fill(ReplayBuffer& buffer, HindsightReplay& her, int envs, int steps, int length) {
  for (int t = 0; t < steps; ++t)
    for (int e = 0; e < envs; ++e) {
      const int step_in_episode = t % length;
      buffer.add(obs(e, step_in_episode), Eigen::VectorXf::Zero(1), -1.0f, obs(e, step_in_episode + 1), false);
      her.added(buffer.last_slot(), e, envs, step_in_episode == length - 1);
    }
}

}  // namespace

TEST_CASE("HER: relabelled goals come from later in the same env's episode, with their reward", "[her]") {
  for (const GoalSelection strategy : {GoalSelection::Future, GoalSelection::Final, GoalSelection::Episode}) {
    INFO("strategy " << static_cast<int>(strategy));
    HerConfig config;
    config.n_sampled_goal = 3;
    config.goal_selection_strategy = strategy;
    ReplayBuffer buffer(1000, 6, 1);
    HindsightReplay her(config, point_goal(), 1000);
    fill(buffer, her, 3, 20, 5);  // 3 envs, 4 finished episodes each
    CHECK(her.relabelable() == 60);
    Rng rng(1);
    ReplayBatch batch;
    her.sample(buffer, 400, rng, batch);
    int relabelled = 0;
    for (int j = 0; j < 400; ++j) {
      const Eigen::VectorXf o = batch.observations.col(j), next = batch.next_observations.col(j);
      CHECK(o[0] == next[0]);  // one env
      CHECK(next[1] == o[1] + 1.0f);
      if (o[3] == 9.0f) {  // a real transition, as stored
        CHECK(batch.rewards[j] == -1.0f);
        CHECK(batch.terminated[j] == 0.0f);
        continue;
      }
      ++relabelled;
      // The new goal was achieved by the same env in the same episode...
      CHECK(o[3] == o[0]);
      CHECK(next.tail(3) == o.tail(3));
      const int here = static_cast<int>(o[1]), goal_step = static_cast<int>(o[4]);
      // ... after step `here` or later (future), at its end (final), anywhere in it (episode).
      if (strategy == GoalSelection::Future) CHECK((goal_step >= here + 1 && goal_step <= 5));
      if (strategy == GoalSelection::Final) CHECK(goal_step == 5);
      if (strategy == GoalSelection::Episode) CHECK((goal_step >= 1 && goal_step <= 5));
      // Reached exactly when it is this transition's own next achieved goal: reward 0 and the end.
      const bool reached = goal_step == here + 1;
      CHECK(batch.rewards[j] == (reached ? 0.0f : -1.0f));
      CHECK(batch.terminated[j] == (reached ? 1.0f : 0.0f));
    }
    CHECK(relabelled == 300);  // 3 / (3 + 1) of the batch
  }
}

TEST_CASE("HER: running episodes and episodes the ring cut are never relabelled", "[her]") {
  HerConfig config;
  ReplayBuffer buffer(20, 6, 1);
  HindsightReplay her(config, point_goal(), 20);
  Rng rng(2);
  ReplayBatch batch;
  fill(buffer, her, 2, 3, 5);  // no episode finished yet: only real transitions
  CHECK(her.relabelable() == 0);
  her.sample(buffer, 50, rng, batch);
  CHECK((batch.observations.row(3).array() == 9.0f).all());
  // Episodes of 5 steps x 2 envs: the 20-slot ring holds two episodes per env; the oldest is
  // dropped the moment its first transition is overwritten.
  ReplayBuffer b2(20, 6, 1);
  HindsightReplay h2(config, point_goal(), 20);
  fill(b2, h2, 2, 10, 5);  // exactly full
  CHECK(h2.relabelable() == 20);
  fill(b2, h2, 2, 1, 5);  // overwrites the first transitions of env 0's and env 1's first episodes
  CHECK(h2.relabelable() == 10);
  h2.sample(b2, 200, rng, batch);
  for (int j = 0; j < 200; ++j)
    if (batch.observations(3, j) != 9.0f) CHECK(batch.observations(3, j) == batch.observations(0, j));
  // An episode longer than the ring never becomes relabelable.
  ReplayBuffer b3(8, 6, 1);
  HindsightReplay h3(config, point_goal(), 8);
  fill(b3, h3, 1, 10, 10);
  CHECK(h3.relabelable() == 0);
}

TEST_CASE("HER: the bookkeeping round-trips through a checkpoint and damaged bytes are refused", "[her]") {
  HerConfig config;
  ReplayBuffer buffer(64, 6, 1);
  HindsightReplay her(config, point_goal(), 64);
  fill(buffer, her, 2, 13, 5);
  std::stringstream state;
  her.save(state, buffer.size());
  HindsightReplay loaded(config, point_goal(), 64);
  loaded.load(state, buffer.size(), "checkpoint.bin");
  CHECK(loaded.relabelable() == her.relabelable());
  Rng r1(5), r2(5);
  ReplayBatch a, b;
  her.sample(buffer, 100, r1, a);
  loaded.sample(buffer, 100, r2, b);
  CHECK(a.observations == b.observations);
  CHECK(a.rewards == b.rewards);
  // The running episodes continue where they were.
  fill(buffer, her, 2, 2, 5);
  CHECK_NOTHROW(loaded.added(0, 0, 2, false));
  CHECK_THROWS_WITH(loaded.added(1, 0, 3, false), Catch::Contains("3 envs") && Catch::Contains("2 envs"));

  std::string bytes = state.str();
  std::stringstream truncated(bytes.substr(0, bytes.size() - 7));
  CHECK_THROWS_WITH(loaded.load(truncated, buffer.size(), "c.bin"), Catch::Contains("c.bin") && Catch::Contains("truncated"));
  std::stringstream wrong_tag("nothing here at all");
  CHECK_THROWS_WITH(loaded.load(wrong_tag, buffer.size(), "c.bin"), Catch::Contains("without \"her\""));
  CHECK_THROWS(HindsightReplay(config, GoalLayout{}, 10));
}
