#include <catch2/catch.hpp>
#include <cstring>
#include <map>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/dqn.hpp"
#include "rdsim/algorithms/n_step_returns.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_setup.hpp"
#include "toy_env.hpp"

using namespace rdsim;
using Eigen::MatrixXf;
using Eigen::VectorXf;

TEST_CASE("TD targets bootstrap on truncation, never on termination", "[dqn]") {
  const VectorXf rewards = (VectorXf(3) << 1.0f, 2.0f, 3.0f).finished();
  // Transition 1 terminated; 0 and 2 did not (2 may have been truncated: it still bootstraps).
  const VectorXf terminated = (VectorXf(3) << 0.0f, 1.0f, 0.0f).finished();
  MatrixXf next_target(2, 3);
  next_target << 5.0f, 7.0f, -1.0f,
                 4.0f, 9.0f, -2.0f;
  const VectorXf y = dqn::td_targets(rewards, terminated, next_target, nullptr, 0.9f);
  CHECK(y[0] == Approx(1.0f + 0.9f * 5.0f));
  CHECK(y[1] == Approx(2.0f));
  CHECK(y[2] == Approx(3.0f + 0.9f * -1.0f));

  // Double Q: the online network picks the action, the target network values it.
  MatrixXf next_online(2, 3);
  next_online << 0.0f, 1.0f, 0.0f,
                 1.0f, 0.0f, 1.0f;
  const VectorXf yd = dqn::td_targets(rewards, terminated, next_target, &next_online, 0.9f);
  CHECK(yd[0] == Approx(1.0f + 0.9f * 4.0f));
  CHECK(yd[1] == Approx(2.0f));
  CHECK(yd[2] == Approx(3.0f + 0.9f * -2.0f));
}

TEST_CASE("TD targets of n-step transitions discount the bootstrap by gamma^steps", "[dqn]") {
  const VectorXf rewards = (VectorXf(3) << 1.0f, 2.0f, 3.0f).finished();
  const VectorXf terminated = (VectorXf(3) << 0.0f, 1.0f, 0.0f).finished();
  const VectorXf steps = (VectorXf(3) << 3.0f, 2.0f, 1.0f).finished();
  MatrixXf next_target(2, 3);
  next_target << 5.0f, 7.0f, -1.0f,
                 4.0f, 9.0f, -2.0f;
  const VectorXf y = dqn::td_targets(rewards, terminated, next_target, nullptr, 0.9f, &steps);
  CHECK(y[0] == Approx(1.0f + 0.729f * 5.0f));
  CHECK(y[1] == Approx(2.0f));  // terminated: no bootstrap, whatever its steps
  CHECK(y[2] == Approx(3.0f + 0.9f * -1.0f));
  // All steps 1: the one-step targets, bit for bit.
  const VectorXf ones = VectorXf::Ones(3);
  CHECK(dqn::td_targets(rewards, terminated, next_target, nullptr, 0.9f, &ones) ==
        dqn::td_targets(rewards, terminated, next_target, nullptr, 0.9f));
}

namespace {

struct Stored {
  float reward, next, terminated, steps;
  int action;
};

// Every transition in `buffer` (observations of one value, distinct per transition), by observation.
std::map<float, Stored> stored(const ReplayBuffer& buffer) {
  std::map<float, Stored> all;
  Rng rng(5);
  ReplayBatch b;
  buffer.sample(2000, rng, b);
  for (int j = 0; j < 2000; ++j)
    all[b.observations(0, j)] = {b.rewards[j], b.next_observations(0, j), b.terminated[j], b.steps[j], b.actions[j]};
  return all;
}

Observation value(float v) {
  Observation o;
  o.values = VectorXf::Constant(1, v);
  return o;
}

}  // namespace

TEST_CASE("n-step returns sum n discounted rewards and flush at an episode's end", "[dqn]") {
  const ObservationSpace space = ObservationSpace::vector(1);
  ReplayBuffer buffer(64, 1);
  NStepReturns n3(3, 0.5, space);
  // Env 0: an episode of 5 steps that terminates; env 1: 2 steps, then truncated. Observation t
  // (env 1: 10 + t), action t % 2, reward t + 1; interleaved as a VecEnv steps them.
  for (int t = 0; t < 5; ++t) {
    n3.add(0, value(float(t)), t % 2, float(t + 1), value(float(t + 1)), t == 4, t == 4, buffer);
    if (t < 2) n3.add(1, value(10.0f + float(t)), t % 2, float(t + 1), value(11.0f + float(t)), false, t == 1, buffer);
    if (t == 1) CHECK(buffer.size() == 2);  // env 1's flush; env 0 still waits for its third reward
  }
  const auto all = stored(buffer);
  REQUIRE(all.size() == 7);
  // Full windows: r_t + 0.5 r_t+1 + 0.25 r_t+2, bootstrapping from s_t+3 with gamma^3.
  CHECK(all.at(0.0f).reward == Approx(1 + 0.5 * 2 + 0.25 * 3));
  CHECK(all.at(0.0f).next == 3.0f);
  CHECK(all.at(0.0f).steps == 3.0f);
  CHECK(all.at(0.0f).terminated == 0.0f);
  CHECK(all.at(2.0f).reward == Approx(3 + 0.5 * 4 + 0.25 * 5));
  CHECK(all.at(2.0f).terminated == 1.0f);  // its window reaches the terminal step
  CHECK(all.at(1.0f).action == 1);
  // The end of the episode: the last steps with the rewards left, all to the terminal state.
  CHECK(all.at(3.0f).reward == Approx(4 + 0.5 * 5));
  CHECK(all.at(3.0f).steps == 2.0f);
  CHECK(all.at(4.0f).reward == Approx(5.0f));
  CHECK(all.at(4.0f).next == 5.0f);
  CHECK(all.at(4.0f).terminated == 1.0f);
  // Truncated: bootstrapped from the final observation, discounted by the steps left.
  CHECK(all.at(10.0f).reward == Approx(1 + 0.5 * 2));
  CHECK(all.at(10.0f).steps == 2.0f);
  CHECK(all.at(10.0f).next == 12.0f);
  CHECK(all.at(10.0f).terminated == 0.0f);
  CHECK(all.at(11.0f).steps == 1.0f);

  // n = 1: each step goes straight into the buffer, unchanged.
  ReplayBuffer direct(8, 1);
  NStepReturns n1(1, 0.5, space);
  n1.add(0, value(7.0f), 1, 0.3f, value(8.0f), false, false, direct);
  CHECK(direct.size() == 1);
  CHECK(stored(direct).at(7.0f).reward == 0.3f);
  CHECK(stored(direct).at(7.0f).steps == 1.0f);
}

TEST_CASE("n-step returns: waiting steps survive save/load, damaged or mismatched state is refused", "[dqn]") {
  const ObservationSpace space = ObservationSpace::vector(1);
  ReplayBuffer a(16, 1), b(16, 1);
  NStepReturns first(3, 0.9, space);
  first.add(0, value(1.0f), 0, 1.0f, value(2.0f), false, false, a);
  first.add(0, value(2.0f), 1, 2.0f, value(3.0f), false, false, a);
  std::stringstream bytes;
  first.save(bytes);
  NStepReturns second(3, 0.9, space);
  second.load(bytes, "ckpt.bin");
  first.add(0, value(3.0f), 0, 3.0f, value(4.0f), false, false, a);
  second.add(0, value(3.0f), 0, 3.0f, value(4.0f), false, false, b);
  REQUIRE(a.size() == 1);
  REQUIRE(b.size() == 1);
  CHECK(stored(a).at(1.0f).reward == stored(b).at(1.0f).reward);
  CHECK(stored(b).at(1.0f).next == 4.0f);

  std::stringstream again;
  first.save(again);
  NStepReturns other_n(2, 0.9, space);
  CHECK_THROWS_WITH(other_n.load(again, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("n_step"));
  std::stringstream wider;
  first.save(wider);
  NStepReturns other_size(3, 0.9, ObservationSpace::vector(2));
  CHECK_THROWS_WITH(other_size.load(wider, "ckpt.bin"), Catch::Contains("wrong size"));
  std::stringstream cut(again.str().substr(0, 20));
  CHECK_THROWS_AS(NStepReturns(3, 0.9, space).load(cut, "ckpt.bin"), Error);
}

TEST_CASE("Huber loss is quadratic near zero, linear beyond 1, with clipped gradients", "[dqn]") {
  const VectorXf pred = (VectorXf(4) << 0.5f, -0.2f, 3.0f, -5.0f).finished();
  const VectorXf target = VectorXf::Zero(4);
  const dqn::TdLoss h = dqn::huber_loss(pred, target);
  CHECK(h.loss == Approx((0.125f + 0.02f + 2.5f + 4.5f) / 4.0f));
  CHECK(h.grad[0] == Approx(0.5f / 4));
  CHECK(h.grad[1] == Approx(-0.2f / 4));
  CHECK(h.grad[2] == Approx(1.0f / 4));
  CHECK(h.grad[3] == Approx(-1.0f / 4));
  // Gradient = derivative of the loss (central differences away from the kinks).
  for (int i = 0; i < 4; ++i) {
    VectorXf p = pred, m = pred;
    p[i] += 1e-3f;
    m[i] -= 1e-3f;
    const float numeric = (dqn::huber_loss(p, target).loss - dqn::huber_loss(m, target).loss) / 2e-3f;
    CHECK(h.grad[i] == Approx(numeric).epsilon(1e-2));
  }
  const dqn::TdLoss s = dqn::squared_loss(pred, target);
  CHECK(s.loss == Approx((0.125f + 0.02f + 4.5f + 12.5f) / 4.0f));
  CHECK(s.grad[3] == Approx(-5.0f / 4));
}

TEST_CASE("epsilon schedule is linear then flat", "[dqn]") {
  CHECK(dqn::epsilon_at(0, 1000, 0.2, 1.0, 0.1) == Approx(1.0));
  CHECK(dqn::epsilon_at(100, 1000, 0.2, 1.0, 0.1) == Approx(0.55));
  CHECK(dqn::epsilon_at(200, 1000, 0.2, 1.0, 0.1) == Approx(0.1));
  CHECK(dqn::epsilon_at(900, 1000, 0.2, 1.0, 0.1) == Approx(0.1));
  CHECK(dqn::epsilon_at(5, 1000, 0.0, 1.0, 0.1) == Approx(0.1));
}

TEST_CASE("replay buffer is a ring and samples only stored transitions", "[dqn]") {
  ReplayBuffer buffer(3, 2);
  Rng rng(1);
  ReplayBatch batch;
  CHECK_THROWS_AS(buffer.sample(4, rng, batch), Error);
  for (int t = 0; t < 5; ++t) {
    const Eigen::Vector2f obs(static_cast<float>(t), 0.0f), next(static_cast<float>(t + 1), 0.0f);
    buffer.add(obs, t % 2, 10.0f * static_cast<float>(t), next, t == 3);
  }
  CHECK(buffer.size() == 3);
  buffer.sample(3000, rng, batch);
  int counts[5] = {0, 0, 0, 0, 0};
  for (int j = 0; j < 3000; ++j) {
    const int t = static_cast<int>(batch.observations(0, j));
    REQUIRE(t >= 2);  // transitions 0 and 1 were overwritten
    ++counts[t];
    // Every field of a sample comes from the same transition.
    CHECK(batch.next_observations(0, j) == static_cast<float>(t + 1));
    CHECK(batch.actions[j] == t % 2);
    CHECK(batch.rewards[j] == 10.0f * static_cast<float>(t));
    CHECK(batch.terminated[j] == (t == 3 ? 1.0f : 0.0f));
  }
  for (int t = 2; t < 5; ++t) CHECK(std::abs(counts[t] - 1000) < 150);  // ~5.8 standard deviations

  Rng a(9), b(9);
  ReplayBatch ba, bb;
  buffer.sample(16, a, ba);
  buffer.sample(16, b, bb);
  CHECK(ba.observations == bb.observations);
}

TEST_CASE("replay buffer save/load round-trips and checks its shape", "[dqn]") {
  ReplayBuffer buffer(4, 3);
  for (int t = 0; t < 6; ++t) buffer.add(VectorXf::Constant(3, float(t)), t, float(t), VectorXf::Constant(3, float(t + 1)), false);
  std::stringstream bytes;
  buffer.save(bytes);
  ReplayBuffer copy(4, 3);
  copy.load(bytes, "ckpt.bin");
  CHECK(copy.size() == 4);
  Rng a(3), b(3);
  ReplayBatch ba, bb;
  buffer.sample(20, a, ba);
  copy.sample(20, b, bb);
  CHECK(ba.observations == bb.observations);
  CHECK(ba.actions == bb.actions);
  // The ring position survives too: the next add overwrites the same slot in both.
  buffer.add(VectorXf::Constant(3, 100.0f), 0, 0.0f, VectorXf::Zero(3), true);
  copy.add(VectorXf::Constant(3, 100.0f), 0, 0.0f, VectorXf::Zero(3), true);
  buffer.sample(20, a, ba);
  copy.sample(20, b, bb);
  CHECK(ba.observations == bb.observations);

  std::stringstream again;
  buffer.save(again);
  ReplayBuffer other(5, 3);
  CHECK_THROWS_WITH(other.load(again, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("buffer_size"));
}

TEST_CASE("replay buffer keeps n-step step counts through save/load, one-step buffers save as before", "[dqn]") {
  ReplayBuffer one(4, 1), multi(4, 1);
  for (int t = 0; t < 3; ++t) {
    one.add(value(float(t)), 0, 1.0f, value(float(t + 1)), false);
    multi.add(value(float(t)), 0, 1.0f, value(float(t + 1)), false, t + 1);
  }
  std::stringstream one_bytes, multi_bytes;
  one.save(one_bytes);
  multi.save(multi_bytes);
  // The step counts are written only when some transition has more than one step.
  CHECK(multi_bytes.str().size() == one_bytes.str().size() + 3 * sizeof(float));
  ReplayBuffer one_copy(4, 1), multi_copy(4, 1);
  one_copy.load(one_bytes, "ckpt.bin");
  multi_copy.load(multi_bytes, "ckpt.bin");
  CHECK(stored(one_copy).at(2.0f).steps == 1.0f);
  CHECK(stored(multi_copy).at(2.0f).steps == 3.0f);
  CHECK(stored(multi_copy).at(0.0f).steps == 1.0f);
  CHECK_THROWS_AS(multi.add(value(9.0f), 0, 1.0f, value(9.0f), false, 0), Error);

  // A damaged step count (0) is refused.
  std::stringstream resave;
  multi.save(resave);
  std::string damaged = resave.str();
  const float zero = 0.0f;
  std::memcpy(damaged.data() + damaged.size() - sizeof(float), &zero, sizeof zero);
  std::stringstream in(damaged);
  ReplayBuffer target(4, 1);
  CHECK_THROWS_WITH(target.load(in, "ckpt.bin"), Catch::Contains("damaged"));
}

namespace {

using toy::Corridor;

Setup corridor_config(std::uint64_t seed) {
  Setup c;
  c.source = "corridor.json";
  c.algorithm = "dqn";
  c.seed = seed;
  c.total_timesteps = 3000;
  c.network.hidden_sizes = {32};
  c.network.activation = "relu";
  c.dqn.learning_rate = 3e-3;
  c.dqn.batch_size = 32;
  c.dqn.buffer_size = 5000;
  c.dqn.learning_starts = 200;
  c.dqn.target_update_interval = 50;
  c.dqn.train_freq = 10;
  c.dqn.gradient_steps = 5;
  c.dqn.exploration_fraction = 0.3;
  c.dqn.exploration_final_eps = 0.05;
  c.dqn.double_q = true;
  return c;
}

VecEnv corridor_envs(std::uint64_t seed) {
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(std::make_unique<Corridor>());
  envs.push_back(std::make_unique<Corridor>());
  return VecEnv(std::move(envs), seed);
}

std::vector<Metrics> train(Algorithm& algo, VecEnv& envs, long long until, long long total) {
  std::vector<Metrics> all;
  while (envs.timesteps() < until) all.push_back(algo.update(envs, {envs.timesteps(), total}));
  return all;
}

}  // namespace

TEST_CASE("DQN learns the corridor and is deterministic", "[dqn]") {
  const Setup config = corridor_config(4);
  VecEnv envs = corridor_envs(4);
  auto algo = make_algorithm(config, envs.spec());
  const std::vector<Metrics> metrics = train(*algo, envs, config.total_timesteps, config.total_timesteps);
  CHECK(envs.timesteps() == config.total_timesteps);  // the last phase stops at the goal
  CHECK(metrics.back()[0].first == "loss");
  CHECK(metrics.back()[3].second == Approx(0.05));  // epsilon reached its final value

  // Greedy policy: right from every cell, so the goal is reached in 5 steps.
  Corridor probe;
  Observation o = probe.reset(std::nullopt);
  Rng rng(0);
  int steps = 0;
  while (steps < 10) {
    const StepResult r = probe.step(algo->act(o, true, rng));
    ++steps;
    if (r.terminated) break;
    o = r.observation;
  }
  CHECK(steps == 5);
  const EpisodeStats stats = envs.episodes().stats();
  CHECK(stats.success_rate > 0.9);

  VecEnv envs2 = corridor_envs(4);
  auto algo2 = make_algorithm(config, envs2.spec());
  CHECK(train(*algo2, envs2, config.total_timesteps, config.total_timesteps) == metrics);
}

TEST_CASE("DQN with n-step returns learns the corridor", "[dqn]") {
  Setup config = corridor_config(5);
  config.dqn.n_step = 3;
  VecEnv envs = corridor_envs(5);
  auto algo = make_algorithm(config, envs.spec());
  train(*algo, envs, config.total_timesteps, config.total_timesteps);
  CHECK(envs.episodes().stats().success_rate > 0.9);
}

TEST_CASE("DQN checkpoint resumes identically, model round-trips", "[dqn]") {
  // One-step returns, and 3-step returns whose waiting steps are part of the checkpoint.
  const int n_step = GENERATE(1, 3);
  CAPTURE(n_step);
  Setup config = corridor_config(7);
  config.dqn.n_step = n_step;
  VecEnv envs = corridor_envs(7);
  auto algo = make_algorithm(config, envs.spec());
  train(*algo, envs, 1000, config.total_timesteps);
  std::stringstream ckpt_algo, ckpt_envs;
  algo->save(ckpt_algo, true);
  envs.save(ckpt_envs);
  const std::vector<Metrics> straight = train(*algo, envs, 1500, config.total_timesteps);

  VecEnv envs2 = corridor_envs(99);
  Setup other = corridor_config(99);
  other.dqn.n_step = n_step;
  auto resumed = make_algorithm(other, envs2.spec());
  resumed->load(ckpt_algo, true, "ckpt.bin");
  REQUIRE(envs2.load(ckpt_envs, "ckpt.bin"));
  CHECK(train(*resumed, envs2, 1500, config.total_timesteps) == straight);

  std::stringstream model;
  algo->save(model, false);
  auto fresh = make_algorithm(corridor_config(1), envs.spec());
  fresh->load(model, false, "model.bin");
  Rng r1(0), r2(0);
  for (int cell = 0; cell < 6; ++cell) {
    Observation o;
    o.values = VectorXf::Zero(6);
    o.values[cell] = 1.0f;
    CHECK(fresh->act(o, true, r1).index == algo->act(o, true, r2).index);
  }
  std::stringstream truncated(model.str().substr(0, model.str().size() / 2));
  CHECK_THROWS_AS(fresh->load(truncated, false, "model.bin"), Error);
}

TEST_CASE("DQN rejects continuous action spaces", "[dqn]") {
  Spec spec;
  spec.env_name = "arm";
  spec.observation.shape = {3};
  spec.action.discrete = false;
  spec.action.low = VectorXf::Constant(2, -1.0f);
  spec.action.high = VectorXf::Constant(2, 1.0f);
  CHECK_THROWS_WITH(make_algorithm(corridor_config(0), spec), Catch::Contains("discrete") && Catch::Contains("corridor.json"));
}

TEST_CASE("DQN network.input_scale: the Q-network sees the observations times the scale", "[dqn]") {
  Setup plain = corridor_config(3);
  plain.network.activation = "tanh";  // not positively homogeneous: scaled inputs change the argmax
  plain.network.hidden_sizes = {16, 16};
  Setup scaled = plain;
  scaled.network.input_scale = 10.0;
  const Spec spec = corridor_envs(3).spec();
  auto a = make_algorithm(plain, spec);
  auto b = make_algorithm(scaled, spec);  // same seed: same initial weights
  Rng obs_rng(5), r1(0), r2(0);
  int differ_unscaled = 0;
  for (int k = 0; k < 200; ++k) {
    Observation o;
    o.values.resize(6);
    for (int i = 0; i < 6; ++i) o.values[i] = static_cast<float>(obs_rng.uniform() - 0.5);
    Observation o10 = o;
    o10.values *= 10.0f;
    const int scaled_action = b->act(o, true, r1).index;
    CHECK(scaled_action == a->act(o10, true, r2).index);
    differ_unscaled += scaled_action != a->act(o, true, r2).index;
  }
  CHECK(differ_unscaled > 0);  // the check above can tell scaled from unscaled inputs
}

TEST_CASE("replay buffer stores Box actions and carries them through save/load", "[replay]") {
  ReplayBuffer buffer(4, 2, 3);
  CHECK(buffer.action_dim() == 3);
  for (int t = 0; t < 6; ++t)
    buffer.add(VectorXf::Constant(2, float(t)), VectorXf::Constant(3, 0.1f * t), float(t), VectorXf::Constant(2, t + 1.0f),
               t == 5);
  CHECK_THROWS_AS(buffer.add(VectorXf::Zero(2), 1, 0.0f, VectorXf::Zero(2), false), Error);  // not an index buffer
  CHECK_THROWS_AS(buffer.add(VectorXf::Zero(2), VectorXf::Zero(2), 0.0f, VectorXf::Zero(2), false), Error);  // 2 values
  Rng rng(1);
  ReplayBatch batch;
  buffer.sample(200, rng, batch);
  REQUIRE(batch.action_values.rows() == 3);
  REQUIRE(batch.action_values.cols() == 200);
  for (int j = 0; j < 200; ++j) {
    const float t = batch.observations(0, j);
    CHECK(t >= 2.0f);  // 0 and 1 were overwritten
    CHECK(batch.action_values.col(j).isApprox(VectorXf::Constant(3, 0.1f * t)));
    CHECK(batch.rewards[j] == t);
    CHECK(batch.terminated[j] == (t == 5.0f ? 1.0f : 0.0f));
  }

  std::stringstream bytes;
  buffer.save(bytes);
  ReplayBuffer copy(4, 2, 3);
  copy.load(bytes, "ckpt.bin");
  Rng a(3), b(3);
  ReplayBatch ba, bb;
  buffer.sample(20, a, ba);
  copy.sample(20, b, bb);
  CHECK(ba.action_values == bb.action_values);
  CHECK(ba.observations == bb.observations);

  std::stringstream again;
  buffer.save(again);
  ReplayBuffer discrete(4, 2);
  CHECK_THROWS_WITH(discrete.load(again, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("Box actions"));
  std::stringstream third;
  buffer.save(third);
  ReplayBuffer wider(4, 2, 4);
  CHECK_THROWS_WITH(wider.load(third, "ckpt.bin"), Catch::Contains("action values"));
}
