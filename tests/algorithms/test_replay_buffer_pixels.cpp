// Pixel observations in DQN's replay buffer: stored as bytes, handed out scaled like the policy's
// input, and carried through checkpoints.
#include <algorithm>
#include <catch2/catch.hpp>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/dqn.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"
#include "algorithm_setup.hpp"
#include "toy_env.hpp"

using namespace rdsim;

namespace {

ObservationSpace pixel_space(int h, int w, int c) {
  ObservationSpace s;
  s.type = ObsType::UInt8;
  s.shape = {h, w, c};
  return s;
}

Observation pixels_of(int size, int seed) {
  Observation o;
  o.pixels.resize(static_cast<std::size_t>(size));
  for (int i = 0; i < size; ++i) o.pixels[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>((i * 7 + seed * 31) % 256);
  return o;
}


Setup pixel_dqn_config(std::uint64_t seed) {
  Setup c;
  c.source = "pixel_corridor.json";
  c.algorithm = "dqn";
  c.seed = seed;
  c.total_timesteps = 2000;
  c.network.cnn.channels = {4};
  c.network.cnn.kernels = {3};
  c.network.cnn.strides = {1};
  c.network.cnn.fc = {16};
  c.dqn.learning_rate = 1e-3;
  c.dqn.batch_size = 16;
  c.dqn.buffer_size = 500;
  c.dqn.learning_starts = 100;
  c.dqn.target_update_interval = 50;
  c.dqn.train_freq = 10;
  c.dqn.gradient_steps = 2;
  return c;
}

VecEnv pixel_corridor_envs(std::uint64_t seed) {
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(std::make_unique<toy::Corridor>(true));
  envs.push_back(std::make_unique<toy::Corridor>(true));
  return VecEnv(std::move(envs), seed);
}

std::vector<Metrics> train(Algorithm& algo, VecEnv& envs, long long until, long long total) {
  std::vector<Metrics> all;
  while (envs.timesteps() < until) all.push_back(algo.update(envs, {envs.timesteps(), total}));
  return all;
}

}  // namespace

TEST_CASE("pixel replay buffer stores bytes and samples the policy's scaled input", "[dqn][pixels]") {
  const ObservationSpace space = pixel_space(4, 5, 3);
  const int size = space.size();
  ReplayBuffer buffer(3, space);
  ReplayBuffer floats(3, size);
  CHECK(buffer.stores_pixels());
  CHECK_FALSE(floats.stores_pixels());
  CHECK(buffer.observation_bytes() == 2u * 3u * static_cast<std::size_t>(size));
  CHECK(floats.observation_bytes() == 4 * buffer.observation_bytes());

  for (int t = 0; t < 4; ++t) buffer.add(pixels_of(size, t), t % 2, static_cast<float>(t), pixels_of(size, t + 1), t == 2);
  CHECK(buffer.size() == 3);
  Rng rng(5);
  ReplayBatch batch;
  buffer.sample(200, rng, batch);
  REQUIRE(batch.observations.rows() == size);
  Eigen::VectorXf expected(size), expected_next(size);
  for (int j = 0; j < 200; ++j) {
    const int t = static_cast<int>(batch.rewards[j]);
    REQUIRE(t >= 1);  // transition 0 was overwritten
    encode_observation(pixels_of(size, t), space, expected);
    encode_observation(pixels_of(size, t + 1), space, expected_next);
    CHECK(batch.observations.col(j) == expected);  // bit-identical to what the policy sees
    CHECK(batch.next_observations.col(j) == expected_next);
    CHECK(batch.actions[j] == t % 2);
    CHECK(batch.terminated[j] == (t == 2 ? 1.0f : 0.0f));
  }

  CHECK_THROWS_WITH(buffer.add(pixels_of(size - 1, 0), 0, 0.0f, pixels_of(size, 0), false), Catch::Contains("pixel bytes"));
  CHECK_THROWS_WITH(buffer.add(Eigen::VectorXf::Zero(size), 0, 0.0f, Eigen::VectorXf::Zero(size), false),
                    Catch::Contains("stores pixels"));
}

TEST_CASE("pixel replay buffer save/load round-trips and refuses a float buffer", "[dqn][pixels]") {
  const ObservationSpace space = pixel_space(2, 2, 3);
  ReplayBuffer buffer(4, space);
  for (int t = 0; t < 6; ++t) buffer.add(pixels_of(12, t), t % 2, float(t), pixels_of(12, t + 3), false);
  std::stringstream bytes;
  buffer.save(bytes);
  // Bytes on disk too: 2 x 4 transitions x 12 values, not 4x that.
  CHECK(bytes.str().size() < 2 * 4 * 12 * 2 + 64);
  ReplayBuffer copy(4, space);
  copy.load(bytes, "ckpt.bin");
  Rng a(3), b(3);
  ReplayBatch ba, bb;
  buffer.sample(20, a, ba);
  copy.sample(20, b, bb);
  CHECK(ba.observations == bb.observations);
  CHECK(ba.next_observations == bb.next_observations);
  CHECK(ba.rewards == bb.rewards);

  std::stringstream again;
  buffer.save(again);
  ReplayBuffer floats(4, 12);
  CHECK_THROWS_WITH(floats.load(again, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("uint8 pixel"));
  std::stringstream float_bytes;
  floats.save(float_bytes);
  CHECK_THROWS_WITH(copy.load(float_bytes, "ckpt.bin"), Catch::Contains("ckpt.bin") && Catch::Contains("float"));
}

TEST_CASE("DQN on pixels: checkpoint resumes identically, model round-trips", "[dqn][pixels]") {
  const Setup config = pixel_dqn_config(7);
  VecEnv envs = pixel_corridor_envs(7);
  auto algo = make_algorithm(config, envs.spec());
  train(*algo, envs, 600, config.total_timesteps);
  std::stringstream ckpt_algo, ckpt_envs;
  algo->save(ckpt_algo, true);
  envs.save(ckpt_envs);
  const std::vector<Metrics> straight = train(*algo, envs, 900, config.total_timesteps);
  REQUIRE_FALSE(straight.empty());

  VecEnv envs2 = pixel_corridor_envs(99);
  auto resumed = make_algorithm(pixel_dqn_config(99), envs2.spec());
  resumed->load(ckpt_algo, true, "ckpt.bin");
  REQUIRE(envs2.load(ckpt_envs, "ckpt.bin"));
  CHECK(train(*resumed, envs2, 900, config.total_timesteps) == straight);

  std::stringstream model;
  algo->save(model, false);
  auto fresh = make_algorithm(pixel_dqn_config(1), envs.spec());
  fresh->load(model, false, "model.bin");
  toy::Corridor probe(true);
  Observation o = probe.reset(std::nullopt);
  Rng r1(0), r2(0);
  for (int i = 0; i < 6; ++i) {
    CHECK(fresh->act(o, true, r1).index == algo->act(o, true, r2).index);
    o = probe.step(Action::discrete(1)).observation;
  }
}
