// Learning from demonstrations: behaviour cloning, the PPO warm start and DQN's demonstration buffer
// on the toy sign env, whose expert is known (discrete: action 1 when s > 0; continuous: 0.5 s).
#include <catch2/catch.hpp>
#include <algorithm>
#include <optional>
#include <set>
#include <sstream>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/algorithms/behavior_cloning.hpp"
#include "rdsim/algorithms/demonstration_replay.hpp"
#include "rdsim/algorithms/demonstration_scatter.hpp"
#include "rdsim/algorithms/dqn.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "toy_env.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;

namespace {

Action expert(const Observation& o, bool discrete) {
  const float s = o.values[0];
  return discrete ? Action::discrete(s > 0 ? 1 : 0) : Action::continuous(Eigen::VectorXf::Constant(1, 0.5f * s));
}

// `noise` makes the demonstrator imprecise, as people are, so that a fit can overfit: Discrete, the share
// of steps with a random action instead; Box, the standard deviation of Gaussian noise on the action.
DemoFile expert_demos(bool discrete, int episodes, std::uint64_t seed = 1, double noise = 0.0) {
  Rng slips(seed);
  toy::SignEnv env(discrete, 10);
  DemoFile f;
  f.path = "toy.demo";
  f.spec = env.spec();
  f.env_config = {{"name", "sign"}};
  for (int k = 0; k < episodes; ++k) {
    DemoEpisode e;
    e.source = DemoSource::Scripted;
    e.seed = seed + static_cast<std::uint64_t>(k);
    e.env_config = f.env_config;
    e.start(env.reset(e.seed));
    while (!e.ended()) {
      Action a = expert(e.observations.back(), discrete);
      if (discrete && slips.uniform() < noise) a = Action::discrete(static_cast<int>(slips.below(2)));
      if (!discrete) a.values[0] = std::clamp(a.values[0] + static_cast<float>(slips.normal(0.0, noise)), -1.0f, 1.0f);
      e.add(a, env.step(a));
    }
    f.episodes.push_back(std::move(e));
  }
  return f;
}

AlgorithmConfig config_for(AlgorithmParams params) {
  AlgorithmConfig c;
  c.params = std::move(params);
  c.network.hidden_sizes = {16, 16};
  return c;
}

DemonstrationsConfig demo_config(int epochs = 60) {
  DemonstrationsConfig c;
  c.file = "toy.demo";
  c.bc_epochs = epochs;
  c.batch_size = 32;
  c.learning_rate = 3e-3;
  c.patience = 5;
  return c;
}

// Share of fresh episodes' steps on which the policy does what the expert would.
double agreement(Algorithm& algo, bool discrete, std::uint64_t seed) {
  toy::SignEnv env(discrete, 10);
  Rng rng(0);
  int same = 0, total = 0;
  for (int k = 0; k < 20; ++k) {
    Observation o = env.reset(seed + static_cast<std::uint64_t>(k));
    for (bool done = false; !done;) {
      const Action a = algo.act(o, true, rng), e = expert(o, discrete);
      same += discrete ? a.index == e.index : std::abs(a.values[0] - e.values[0]) < 0.1f;
      ++total;
      StepResult r = env.step(a);
      done = r.terminated || r.truncated;
      o = std::move(r.observation);
    }
  }
  return static_cast<double>(same) / total;
}

}  // namespace

TEST_CASE("demonstrations split by whole episodes, with discounted returns", "[demos][bc]") {
  const DemoFile f = expert_demos(true, 10);
  Rng rng(3);
  const DemoSplit split = split_demonstrations(f, f.spec.observation, 0.2, 0.5, rng);
  CHECK(split.train.episodes == 8);
  CHECK(split.validation.episodes == 2);
  CHECK(split.train.size() == 80);
  CHECK(split.validation.size() == 20);
  // The expert earns 1 every step: the return to go of the last step is 1, before it 1 + 0.5, ...
  CHECK(split.train.returns[9] == Approx(1.0));
  CHECK(split.train.returns[8] == Approx(1.5));
  CHECK(split.train.returns[0] == Approx(2.0 * (1.0 - std::pow(0.5, 10))));
  Rng one(3);
  CHECK(split_demonstrations(expert_demos(true, 1), f.spec.observation, 0.2, 0.5, one).validation.size() == 0);
}

TEST_CASE("behaviour cloning copies the expert and stops early on held-out episodes", "[demos][bc]") {
  for (bool discrete : {true, false}) {
    INFO((discrete ? "Discrete" : "Box"));
    const DemoFile f = expert_demos(discrete, 20, 1, 0.15);
    auto algo = make_algorithm(config_for(BcConfig{}), 1, f.spec);
    CHECK(agreement(*algo, discrete, 500) < 0.9);
    Rng rng = Rng::derive(1, rng_stream::demonstrations);
    const std::vector<Metrics> rows = algo->learn_from_demonstrations(f, demo_config(400), rng, true);
    REQUIRE(!rows.empty());
    CHECK(rows.size() < 400);  // the patience ran out before the epochs did
    CHECK(rows.front()[0].first == "epoch");
    CHECK(rows.back()[3].first == "actor_val_error");
    CHECK(rows.back()[3].second < (discrete ? 0.25 : 0.2));  // against the imprecise demonstrator
    CHECK(agreement(*algo, discrete, 500) > (discrete ? 0.98 : 0.9));  // unseen seeds (Box: within 0.1)

    // The model round-trips and acts the same.
    std::stringstream model;
    algo->save(model, false);
    auto loaded = make_algorithm(config_for(BcConfig{}), 2, f.spec);
    loaded->load(model, false, "model");
    CHECK(agreement(*loaded, discrete, 900) == agreement(*algo, discrete, 900));
  }
}

TEST_CASE("bc runs the cloned policy in the envs, it must learn first", "[demos][bc]") {
  const DemoFile f = expert_demos(true, 10);
  VecEnv envs(toy::make_envs(2), 4);
  auto algo = make_algorithm(config_for(BcConfig{16, true}), 1, f.spec);
  CHECK_THROWS_WITH(algo->update(envs, {0, 100}), Contains("has not learnt from demonstrations"));
  Rng rng(1);
  algo->learn_from_demonstrations(f, demo_config(), rng, true);
  const Metrics m = algo->update(envs, {0, 100});
  CHECK(envs.timesteps() == 32);
  CHECK(m[0].first == "fit_epochs");
  CHECK(envs.episodes().stats().success_rate == 1.0);
  CHECK(envs.episodes().stats().mean_return == Approx(10.0));
}

TEST_CASE("the PPO warm start clones the actor and fits the critic to the demonstrated returns", "[demos][ppo]") {
  const DemoFile f = expert_demos(true, 20);
  PpoConfig ppo;
  ppo.gamma = 0.9;
  auto algo = make_algorithm(config_for(ppo), 1, f.spec);
  Rng rng(5);
  const std::vector<Metrics> rows = algo->learn_from_demonstrations(f, demo_config(300), rng, true);
  REQUIRE(rows.back().size() == 6);
  CHECK(rows.back()[4].first == "critic_loss");
  CHECK(rows.back()[5].second < 0.05);  // validation squared error of V against the returns
  CHECK(agreement(*algo, true, 700) > 0.98);
  // Nothing happens on a resumed run: its checkpoint holds the pre-trained weights.
  CHECK(algo->learn_from_demonstrations(f, demo_config(), rng, false).empty());
}

TEST_CASE("PPO and A2C keep a decaying cloning term during RL with demonstrations.bc_weight", "[demos][ppo]") {
  const DemoFile f = expert_demos(true, 10);
  PpoConfig ppo;
  ppo.n_steps = 16;
  ppo.batch_size = 16;
  ppo.n_epochs = 1;
  A2cConfig a2c;
  a2c.n_steps = 8;
  for (const AlgorithmParams& params : {AlgorithmParams(ppo), AlgorithmParams(a2c)}) {
    auto algo = make_algorithm(config_for(params), 1, f.spec);
    DemonstrationsConfig demos = demo_config(5);
    demos.bc_weight = 0.5;
    demos.bc_weight_decay = 0.5;
    Rng rng(2);
    algo->learn_from_demonstrations(f, demos, rng, true);
    VecEnv envs(toy::make_envs(2), 3);
    const Metrics first = algo->update(envs, {0, 1000}), second = algo->update(envs, {envs.timesteps(), 1000});
    REQUIRE(first.back().first == "demo_bc_weight");
    CHECK(first.back().second == Approx(0.5));
    CHECK(second.back().second == Approx(0.25));
    CHECK(first[first.size() - 2].first == "demo_bc_loss");
    CHECK(first[first.size() - 2].second > 0.0);
  }
  // Without the term the columns are not there.
  auto plain = make_algorithm(config_for(ppo), 1, f.spec);
  VecEnv envs(toy::make_envs(2), 3);
  CHECK(plain->update(envs, {0, 1000}).back().first == "minibatches");
}

TEST_CASE("DQfD's large-margin loss: zero once the demonstrated action leads by the margin", "[demos][dqn]") {
  Eigen::MatrixXf q(3, 2);
  q << 1.0f, 0.0f,  //
      0.5f, 2.0f,   //
      0.0f, 0.0f;
  Eigen::VectorXi demo(2);
  demo << 0, 0;
  const dqn::TdLoss l = dqn::large_margin_loss(q, demo, 0.8f);
  // Column 0: max(1, 0.5 + 0.8, 0 + 0.8) - 1 = 0.3; column 1: (2 + 0.8) - 0 = 2.8; mean 1.55.
  CHECK(l.loss == Approx(1.55));
  CHECK(l.grad[1] == Approx(0.5));   // column 0, action 1 pushed down
  CHECK(l.grad[0] == Approx(-0.5));  // column 0, the demonstrated action pulled up
  CHECK(l.grad[4] == Approx(0.5));
  CHECK(l.grad[3] == Approx(-0.5));
  q(0, 0) = 2.0f;
  q(0, 1) = 3.0f;
  CHECK(dqn::large_margin_loss(q, demo, 0.8f).loss == Approx(0.0));
}

TEST_CASE("DQN pre-trained on demonstrations acts like the expert and keeps them in its own buffer", "[demos][dqn]") {
  const DemoFile f = expert_demos(true, 20);
  DqnConfig dqn;
  dqn.learning_starts = 0;
  dqn.batch_size = 32;
  dqn.buffer_size = 1000;
  dqn.gamma = 0.5;
  DemonstrationsConfig demos = demo_config(60);
  demos.large_margin = true;
  auto algo = make_algorithm(config_for(dqn), 1, f.spec);
  Rng rng(2);
  const std::vector<Metrics> rows = algo->learn_from_demonstrations(f, demos, rng, true);
  REQUIRE(rows.size() == 60);
  CHECK(rows.back()[2].first == "margin_loss");
  CHECK(rows.back()[2].second < rows.front()[2].second);
  CHECK(agreement(*algo, true, 300) > 0.98);
  // Training draws from both buffers and reports the margin loss.
  VecEnv envs(toy::make_envs(1), 3);
  const Metrics m = algo->update(envs, {0, 1000});
  CHECK(m.back().first == "margin_loss");
}

TEST_CASE("DQN refuses demonstrations without a step", "[demos][dqn]") {
  const DemoFile f = expert_demos(true, 2);
  DemoFile empty = f;
  empty.episodes.clear();
  auto dqn = make_algorithm(config_for(DqnConfig{}), 1, f.spec);
  Rng rng(1);
  CHECK_THROWS_WITH(dqn->learn_from_demonstrations(empty, demo_config(), rng, true), Contains("holds no demonstrated step"));
}

TEST_CASE("SAC and TD3 pre-train on demonstrations, keep a share of every minibatch and clone with a Q-filter",
          "[demos][sac][td3]") {
  // normalize_observations too: the statistics start from the demonstrations.
  for (const auto& [name, normalize] : {std::pair{"sac", false}, {"td3", false}, {"sac", true}}) {
    INFO(name << (normalize ? " with normalize_observations" : ""));
    const DemoFile f = expert_demos(false, 20);
    AlgorithmConfig c = config_for(default_algorithm_params(name));
    std::visit(
        [](auto& p) {
          if constexpr (std::is_base_of_v<OffPolicyConfig, std::decay_t<decltype(p)>>) {
            p.learning_rate = 3e-3;
            p.batch_size = 64;
            p.buffer_size = 2000;
            p.learning_starts = 100;
            p.gamma = 0.5;
          }
        },
        c.params);
    DemonstrationsConfig demos;
    demos.file = "toy.demo";
    demos.bc_epochs = 150;
    demos.bc_weight = 20.0;
    demos.demo_fraction = 0.25;
    c.normalize_observations = normalize;
    auto algo = make_algorithm(c, 2, f.spec);
    CHECK(agreement(*algo, false, 700) < 0.5);
    Rng rng(1);
    const std::vector<Metrics> rows = algo->learn_from_demonstrations(f, demos, rng, true);
    REQUIRE(rows.size() == 150);
    CHECK(rows.front().front().first == "epoch");
    CHECK(rows.back().back().first == "bc_loss");
    // The demonstrations alone (200 steps, gradient steps of the method's own losses plus the cloning
    // term) make the policy the expert's.
    CHECK(agreement(*algo, false, 700) > 0.8);
    // RL then keeps a quarter of every minibatch demonstrated and reports the cloning loss.
    VecEnv envs(toy::make_envs(2, false), 2);
    Metrics m;
    while (envs.timesteps() < 400) m = algo->update(envs, {envs.timesteps(), 400});
    CHECK(std::find_if(m.begin(), m.end(), [](const auto& kv) { return kv.first == "bc_loss"; }) != m.end());
    CHECK(agreement(*algo, false, 700) > 0.8);
    // Resuming rebuilds the buffer without pre-training.
    auto resumed = make_algorithm(c, 2, f.spec);
    CHECK(resumed->learn_from_demonstrations(f, demos, rng, false).empty());
  }
}

namespace {

// A goal env's spec as the manipulation tasks name it (one cube): rows 0-2 the effector, 3-5 its
// velocity, 6 the fingers, 7-9 the cube, 10-12 cube - effector, 13-15 achieved, 16-18 desired.
Spec cube_goal_spec() {
  Spec s;
  s.env_name = "cube";
  s.observation.shape = {19};
  s.observation.parts = {{"effector_position", 3}, {"effector_velocity", 3}, {"finger_opening", 1},
                         {"cube1_position", 3},    {"cube1_from_effector", 3}, {"achieved_goal", 3},
                         {"desired_goal", 3}};
  s.action = ActionSpace{.discrete = false, .n = 0, .low = Eigen::VectorXf::Constant(4, -1.0f),
                         .high = Eigen::VectorXf::Constant(4, 1.0f)};
  s.goal = GoalLayout{.observation = 13, .points = 1, .distance_threshold = 0.05f, .reward = GoalReward::Sparse};
  return s;
}

// One demonstrated step of `spec`: every value distinct, the cube 0.1 m from its goal.
DemoFile one_step(const Spec& spec) {
  DemoFile f;
  f.path = "cube.demo";
  f.spec = spec;
  DemoEpisode e;
  Observation first{Eigen::VectorXf::LinSpaced(19, 0.0f, 1.8f), {}}, next = first;
  next.values.array() += 0.01f;
  first.values.segment(13, 3) = first.values.segment(7, 3);
  next.values.segment(13, 3) = next.values.segment(7, 3);
  first.values.segment(16, 3) = first.values.segment(13, 3);
  first.values[16] += 0.1f;
  next.values.segment(16, 3) = first.values.segment(16, 3);
  e.start(first);
  StepResult r{.observation = next, .reward = -1.0f, .terminated = false, .truncated = true, .info = {}};
  e.add(Action::continuous(Eigen::Vector4f(0.2f, -0.3f, 0.1f, 1.0f)), r);
  f.episodes.push_back(std::move(e));
  return f;
}

}  // namespace

TEST_CASE("demonstrations.shift moves every world position of a drawn transition by one planar offset", "[demos][sac]") {
  const Spec spec = cube_goal_spec();
  CHECK(planar_position_rows(spec) == std::vector<int>{0, 7, 13, 16});
  Spec joints = spec;  // control "joints": the actions are per joint, a shift does not carry them over
  joints.observation.parts.insert(joints.observation.parts.begin() + 3, {"joint_positions", 6});
  CHECK(planar_position_rows(joints).empty());
  Spec no_goal = spec;
  no_goal.goal = GoalLayout{};
  CHECK(planar_position_rows(no_goal).empty());

  const DemoFile f = one_step(spec);
  const auto identity = [](const Action& a) -> Eigen::VectorXf { return a.values; };
  const DemoEpisode& e = f.episodes.front();
  const int batch = 64;
  const auto draw = [&](double shift, const std::optional<HerConfig>& her) {
    DemonstrationReplay replay(f, spec, her, identity, shift);
    ReplayBatch out;
    replay.buffer().shape_batch(batch, out);
    Rng rng(3);
    replay.sample_into(0, batch, rng, out);
    return out;
  };
  const ReplayBatch plain = draw(0.0, std::nullopt);
  for (int j = 0; j < batch; ++j) {
    CHECK(plain.observations.col(j) == e.observations[0].values);
    CHECK(plain.next_observations.col(j) == e.observations[1].values);
  }
  for (const bool her : {false, true}) {
    INFO("her " << her);
    const ReplayBatch moved = draw(0.1, her ? std::optional<HerConfig>(HerConfig{}) : std::nullopt);
    std::set<float> offsets;
    for (int j = 0; j < batch; ++j) {
      const Eigen::VectorXf d = moved.observations.col(j) - e.observations[0].values;
      const Eigen::VectorXf dn = moved.next_observations.col(j) - e.observations[1].values;
      const float dx = d[0], dy = d[1];
      CHECK(std::abs(dx) <= 0.1f);
      CHECK(std::abs(dy) <= 0.1f);
      offsets.insert(dx);
      for (const int r : {0, 7}) {  // the effector and the cube, before and after, by the same offset
        CHECK(d[r] == Approx(dx).margin(1e-6));
        CHECK(d[r + 1] == Approx(dy).margin(1e-6));
        CHECK(dn[r] == Approx(dx).margin(1e-6));
        CHECK(dn[r + 1] == Approx(dy).margin(1e-6));
      }
      for (const int r : {2, 3, 4, 5, 6, 9, 10, 11, 12, 15}) {  // heights, velocities, fingers, relative
        CHECK(d[r] == Approx(0.0f).margin(1e-6));
        CHECK(dn[r] == Approx(0.0f).margin(1e-6));
      }
      // The goals move with the scene (relabelled ones too): the reward and the action stay.
      const Eigen::VectorXf o = moved.next_observations.col(j);
      const Eigen::VectorXf& recorded = e.observations[1].values;
      const auto gap = [&](const float* v, int axis) { return v[16 + axis] - v[13 + axis]; };  // desired - achieved
      const bool as_recorded = std::abs(gap(o.data(), 0) - gap(recorded.data(), 0)) < 1e-5f &&
                               std::abs(gap(o.data(), 1) - gap(recorded.data(), 1)) < 1e-5f;
      const bool relabelled = std::abs(gap(o.data(), 0)) < 1e-5f && std::abs(gap(o.data(), 1)) < 1e-5f;
      CHECK((as_recorded || (her && relabelled)));
      CHECK(moved.rewards[j] == spec.goal.reward_of(o.data() + 13, o.data() + 16));
      CHECK(moved.action_values.col(j) == e.actions[0].values);
    }
    CHECK(offsets.size() > batch / 2);  // each transition its own offset
  }
}
namespace {

// stack's observation in short (two cubes): rows 0-2 the effector, 3-5 cube 1, 6-8 cube 1 - effector,
// 9-11 cube 2, 12-14 cube 2 - effector, 15-20 achieved (the cubes), 21-26 desired (goal 2 above goal 1).
Spec two_cube_spec() {
  Spec s;
  s.env_name = "two_cubes";
  s.observation.shape = {27};
  s.observation.parts = {{"effector_position", 3}, {"cube1_position", 3}, {"cube1_from_effector", 3},
                         {"cube2_position", 3},    {"cube2_from_effector", 3}, {"achieved_goal", 6},
                         {"desired_goal", 6}};
  s.action = ActionSpace{.discrete = false, .n = 0, .low = Eigen::VectorXf::Constant(4, -1.0f),
                         .high = Eigen::VectorXf::Constant(4, 1.0f)};
  s.goal = GoalLayout{.observation = 15, .points = 2, .distance_threshold = 0.05f, .reward = GoalReward::Sparse};
  return s;
}

// Eight steps of stacking, cubes starting at `a` and `b`, the goal at `g` (x, y): cube 1 lifted in
// observations 3-4 and put on the goal from 5 on, cube 2 lifted from 7 on. The effector's x is
// 0.01 m x the observation's index (which step a drawn transition is).
DemoEpisode stacking(const Eigen::Vector2f& a, const Eigen::Vector2f& b, const Eigen::Vector2f& g) {
  const auto observe = [&](int t) {
    const Eigen::Vector3f ee(0.01f * static_cast<float>(t), 0.0f, 0.3f);
    const Eigen::Vector3f goal(g.x(), g.y(), 0.02f), cube1 = t < 3   ? Eigen::Vector3f(a.x(), a.y(), 0.02f)
                                                        : t < 5   ? Eigen::Vector3f(a.x(), a.y(), 0.05f * static_cast<float>(t - 2))
                                                                  : goal;
    const Eigen::Vector3f cube2 = t < 7 ? Eigen::Vector3f(b.x(), b.y(), 0.02f) : Eigen::Vector3f(b.x(), b.y(), 0.1f);
    const Eigen::Vector3f parts[] = {ee, cube1, cube1 - ee, cube2, cube2 - ee, cube1, cube2, goal, goal + Eigen::Vector3f(0.0f, 0.0f, 0.04f)};
    Eigen::VectorXf v(27);
    for (int p = 0; p < 9; ++p)
      for (int i = 0; i < 3; ++i) v[3 * p + i] = parts[p][i];
    return Observation{v, {}};
  };
  DemoEpisode e;
  e.start(observe(0));
  for (int t = 1; t <= 8; ++t) {
    StepResult r{.observation = observe(t), .reward = -1.0f, .terminated = false, .truncated = t == 8, .info = {}};
    e.add(Action::continuous(Eigen::Vector4f(0.1f, 0.0f, 0.0f, static_cast<float>(t))), r);
  }
  return e;
}

}  // namespace

TEST_CASE("demonstrations.scatter moves the cubes and the goal a demonstrated step does not depend on", "[demos][sac]") {
  const Spec spec = two_cube_spec();
  CHECK(DemonstrationScatter::supported(spec));
  CHECK(DemonstrationScatter::supported(cube_goal_spec()));  // push, pick_and_place: one cube
  Spec reach;  // no object but the effector
  reach.observation.shape = {9};
  reach.observation.parts = {{"effector_position", 3}, {"achieved_goal", 3}, {"desired_goal", 3}};
  reach.goal = GoalLayout{.observation = 3, .points = 1};
  CHECK_FALSE(DemonstrationScatter::supported(reach));

  DemoFile f;
  f.path = "stack.demo";
  f.spec = spec;
  f.episodes = {stacking({0.15f, -0.15f}, {-0.15f, 0.15f}, {0.0f, 0.1f}), stacking({-0.1f, -0.1f}, {0.1f, 0.15f}, {0.1f, -0.15f})};
  // Cube 2 is idle until cube 1 is on its goal (observation 5), the goal until cube 1 moves (3).
  const DemonstrationScatter idle(f, spec, true);
  for (int slot = 0; slot < 16; ++slot) {
    const int t = slot % 8;
    INFO("step " << t);
    CHECK(idle.idle(slot) == ((t < 4 ? 0x02 : 0) | (t < 2 ? DemonstrationScatter::kGoalBit : 0)));
  }
  CHECK(DemonstrationScatter(f, spec, false).idle(0) == 0x02);

  const auto identity = [](const Action& a) -> Eigen::VectorXf { return a.values; };
  const int batch = 256;
  for (const bool her : {false, true}) {
    INFO("her " << her);
    const std::optional<HerConfig> h = her ? std::optional<HerConfig>(HerConfig{}) : std::nullopt;
    const auto draw = [&](double scatter) {
      DemonstrationReplay replay(f, spec, h, identity, 0.0, scatter, true);
      ReplayBatch out;
      replay.buffer().shape_batch(batch, out);
      Rng rng(7);
      replay.sample_into(0, batch, rng, out);
      return out;
    };
    const ReplayBatch plain = draw(0.0), moved = draw(1.0), again = draw(1.0);
    CHECK(moved.observations == again.observations);  // the same draws for the same stream
    int cubes_moved = 0, goals_moved = 0;
    for (int j = 0; j < batch; ++j) {
      const int t = static_cast<int>(std::lround(plain.observations(0, j) / 0.01f));
      INFO("column " << j << ", step " << t);
      const Eigen::VectorXf o = moved.observations.col(j), n = moved.next_observations.col(j);
      const Eigen::VectorXf d = o - plain.observations.col(j), dn = n - plain.next_observations.col(j);
      const Eigen::Vector2f by = d.segment<2>(9), goal_by = d.segment<2>(21);  // cube 2's offset, the goal's
      const bool cube = by.norm() > 1e-6f, goal = goal_by.norm() > 1e-6f;
      cubes_moved += cube;
      goals_moved += goal;
      CHECK((!cube || t < 4));
      CHECK((!goal || t < 2));
      for (const int r : {9, 12, 18}) {  // cube 2, from the effector, its achieved point: one offset, both observations
        CHECK(d.segment<2>(r).isApprox(by, 1e-5f));
        CHECK(dn.segment<2>(r).isApprox(by, 1e-5f));
      }
      for (const int r : {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 14, 15, 16, 17, 20, 23, 26}) {  // the effector, cube 1, heights
        CHECK(d[r] == 0.0f);
        CHECK(dn[r] == 0.0f);
      }
      CHECK(dn.segment<6>(21) == d.segment<6>(21));
      // The second desired point is cube 2's: one it meets where it lies (a hindsight goal) moves
      // with it, any other with the goal.
      const bool tied = (plain.observations.col(j).segment<3>(9) - plain.observations.col(j).segment<3>(24)).norm() < 0.05f;
      CHECK(d.segment<2>(24).isApprox(tied ? by : goal_by, 1e-5f));
      if (cube) {  // clear of the effector, cube 1 and the goals it does not meet, where the demonstrations' cubes started
        const Eigen::Vector2f at = o.segment<2>(9);
        CHECK((at - o.head<2>()).norm() >= 0.1f);
        CHECK((at - n.head<2>()).norm() >= 0.1f);
        CHECK((at - o.segment<2>(3)).norm() >= 0.06f);
        CHECK((at.array() >= -0.15f - 1e-6f).all());
        CHECK((at.array() <= 0.15f + 1e-6f).all());
        CHECK((at - o.segment<2>(21)).norm() >= 0.06f);
        if (!tied) CHECK((at - o.segment<2>(24)).norm() >= 0.06f);
      }
      if (goal) {  // where the demonstrations' goals were, clear of the cubes
        CHECK(o[21] >= 0.0f - 1e-6f);
        CHECK(o[21] <= 0.1f + 1e-6f);
        CHECK(o[22] >= -0.15f - 1e-6f);
        CHECK(o[22] <= 0.1f + 1e-6f);
        CHECK((o.segment<2>(21) - o.segment<2>(3)).norm() >= 0.06f);
      }
      CHECK(moved.rewards[j] == spec.goal.reward_of(n.data() + 15, n.data() + 21));
      CHECK(moved.terminated[j] == (spec.goal.is_success(n.data() + 15, n.data() + 21) ? 1.0f : 0.0f));
      CHECK(moved.action_values.col(j) == plain.action_values.col(j));
    }
    CHECK(cubes_moved > batch / 4);  // half the steps have cube 2 idle
    CHECK(goals_moved > batch / 16);  // a quarter have the goal idle
  }
}
