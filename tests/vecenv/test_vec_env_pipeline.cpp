// VecEnv's pipelined groups (send / recv): the same env steps as step(), on any thread count.
#include <catch2/catch.hpp>

#include "../algorithms/toy_env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/vecenv/vec_env.hpp"

namespace {

using namespace rdsim;

// Envs that any worker may step (what lets the groups overlap), `terminate_at` ending some episodes early.
std::vector<std::unique_ptr<Env>> movable_envs(int n, bool movable = true) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) {
    auto e = std::make_unique<toy::SignEnv>(true, 5 + i % 3, i % 2 ? 3 : 0);
    e->any_thread = movable;
    envs.push_back(std::move(e));
  }
  return envs;
}

// The action of env i at batch step t: a fixed pattern that differs between envs and steps.
Action action_at(int t, int i) { return Action::discrete((t * 7 + i * 3) % 5 < 2 ? 1 : 0); }

struct Trace {
  std::vector<float> rewards, observations;
  std::vector<EpisodeRecord> episodes;
};

Trace run_step(int envs, int threads, int steps) {
  VecEnv vec(movable_envs(envs), 11, 20, threads);
  Trace trace;
  std::vector<Action> actions(static_cast<std::size_t>(envs));
  for (int t = 0; t < steps; ++t) {
    for (int i = 0; i < envs; ++i) actions[static_cast<std::size_t>(i)] = action_at(t, i);
    const auto& results = vec.step(actions);
    for (int i = 0; i < envs; ++i) {
      trace.rewards.push_back(results[static_cast<std::size_t>(i)].reward);
      for (float v : vec.observation(i).values) trace.observations.push_back(v);
    }
  }
  trace.episodes = vec.episodes().take_finished();
  CHECK(vec.timesteps() == static_cast<long long>(envs) * steps);
  return trace;
}

// The rollout's pattern: group g's results are read right after recv(g), its next actions sent at once.
Trace run_groups(int envs, int threads, int groups, int steps, bool movable = true) {
  VecEnv vec(movable_envs(envs, movable), 11, 20, threads);
  vec.set_groups(groups);
  Trace trace;
  std::vector<float> rewards(static_cast<std::size_t>(envs)), observations;
  std::vector<std::vector<float>> obs(static_cast<std::size_t>(envs));
  std::vector<Action> actions(static_cast<std::size_t>(envs));
  for (int t = 0; t <= steps; ++t) {
    for (int g = 0; g < groups; ++g) {
      if (t > 0) {
        const auto& results = vec.recv(g);
        for (int i = vec.group_first(g); i < vec.group_end(g); ++i) {
          rewards[static_cast<std::size_t>(i)] = results[static_cast<std::size_t>(i)].reward;
          const Observation o = vec.observation(i);
          obs[static_cast<std::size_t>(i)].assign(o.values.data(), o.values.data() + o.values.size());
        }
      }
      if (t == steps) continue;
      for (int i = vec.group_first(g); i < vec.group_end(g); ++i) actions[static_cast<std::size_t>(i)] = action_at(t, i);
      vec.send(g, actions);
    }
    if (t == 0) continue;
    for (int i = 0; i < envs; ++i) {
      trace.rewards.push_back(rewards[static_cast<std::size_t>(i)]);
      for (float v : obs[static_cast<std::size_t>(i)]) trace.observations.push_back(v);
    }
  }
  CHECK(vec.in_flight() == 0);
  trace.episodes = vec.episodes().take_finished();
  CHECK(vec.timesteps() == static_cast<long long>(envs) * steps);
  return trace;
}

void check_same(const Trace& a, const Trace& b) {
  CHECK(a.rewards == b.rewards);
  CHECK(a.observations == b.observations);
  REQUIRE(a.episodes.size() == b.episodes.size());
  for (std::size_t k = 0; k < a.episodes.size(); ++k) {
    CHECK(a.episodes[k].episode == b.episodes[k].episode);
    CHECK(a.episodes[k].timesteps == b.episodes[k].timesteps);
    CHECK(a.episodes[k].episode_return == b.episodes[k].episode_return);
    CHECK(a.episodes[k].length == b.episodes[k].length);
  }
}

}  // namespace

TEST_CASE("VecEnv groups: send/recv step every env as step() does, on any thread count", "[vec_env][pipeline]") {
  const Trace reference = run_step(7, 1, 60);
  REQUIRE(reference.episodes.size() > 20);
  const int threads = GENERATE(1, 2, 3);
  const int groups = GENERATE(2, 3, 7);
  INFO("threads " << threads << ", groups " << groups);
  check_same(run_groups(7, threads, groups, 60), reference);
  // Envs bound to their worker's thread step one group at a time in recv(): the same again.
  check_same(run_groups(7, threads, groups, 60, false), reference);
}

TEST_CASE("VecEnv groups: out-of-turn calls and steps while groups are in flight are clear errors", "[vec_env][pipeline]") {
  const int threads = GENERATE(1, 2);
  VecEnv vec(movable_envs(4), 3, 20, threads);
  const std::vector<Action> actions(4, Action::discrete(1));
  CHECK_THROWS_WITH(vec.set_groups(5), "VecEnv::set_groups: expected 1..4 groups (one env at least in each), got 5");
  vec.set_groups(2);
  CHECK(vec.group_first(1) == 2);
  CHECK_THROWS_AS(vec.recv(0), Error);  // nothing sent
  CHECK_THROWS_AS(vec.send(1, actions), Error);
  vec.send(0, actions);
  CHECK_THROWS_WITH(vec.step(actions), "VecEnv::step: 1 group(s) sent and not received; recv() them first");
  CHECK_THROWS_AS(vec.set_groups(1), Error);
  CHECK_THROWS_AS(vec.send(0, actions), Error);
  CHECK_THROWS_AS(vec.send(1, std::vector<Action>(3, Action::discrete(1))), Error);
  vec.send(1, actions);
  CHECK_THROWS_AS(vec.recv(1), Error);
  vec.recv(0);
  vec.recv(1);
  CHECK(vec.timesteps() == 4);
  vec.step(actions);  // idle again
  CHECK(vec.timesteps() == 8);
}

namespace {

// Throws on its `fail_at`-th step.
class FailingEnv final : public Env {
public:
  explicit FailingEnv(int fail_at) : fail_at_(fail_at) { inner_.any_thread = true; }
  const Spec& spec() const override { return inner_.spec(); }
  bool steps_on_any_thread() const override { return true; }
  Observation reset(std::optional<std::uint64_t> seed) override { return inner_.reset(seed); }
  StepResult step(const Action& a) override {
    if (++steps_ == fail_at_) throw Error("env broke at step " + std::to_string(steps_));
    return inner_.step(a);
  }

private:
  toy::SignEnv inner_{true, 50};
  int fail_at_, steps_ = 0;
};

}  // namespace

TEST_CASE("VecEnv groups: an env's error comes up at its group's recv, and the VecEnv goes on", "[vec_env][pipeline]") {
  const int threads = GENERATE(1, 2);
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<FailingEnv>(i == 2 ? 3 : 1000));
  VecEnv vec(std::move(envs), 5, 20, threads);
  vec.set_groups(2);
  const std::vector<Action> actions(4, Action::discrete(1));
  vec.send(0, actions);
  vec.send(1, actions);
  for (int t = 1; t < 3; ++t) {
    vec.recv(0);
    vec.send(0, actions);
    vec.recv(1);
    vec.send(1, actions);
  }
  vec.recv(0);
  CHECK_THROWS_WITH(vec.recv(1), "env broke at step 3");
  CHECK(vec.in_flight() == 0);
  vec.step(actions);
  // A VecEnv destroyed with groups in flight lets them finish first (no hang, no step left running).
  vec.send(0, actions);
  vec.send(1, actions);
}
