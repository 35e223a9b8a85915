// CNN policies (network.cnn) on a pixel toy task, for every algorithm that builds them.
#include <catch2/catch.hpp>
#include <sstream>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/nn/cnn.hpp"

using namespace rdsim;

namespace {

// A 16x16 RGB image, black but for a bright 4x4 square in the left or right half (random side
// and height each step). Action 0 = left, 1 = right; reward 1 for naming the square's side.
// Episodes are truncated after 10 steps. Only a network that reads the pixels can beat 5.
class SquareSideEnv final : public rdsim::Env {
public:
  SquareSideEnv() {
    spec_.env_name = "square_side";
    spec_.observation.type = rdsim::ObsType::UInt8;
    spec_.observation.shape = {16, 16, 3};
    spec_.action.discrete = true;
    spec_.action.n = 2;
    spec_.max_episode_steps = 10;
  }
  const rdsim::Spec& spec() const override { return spec_; }
  rdsim::Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override {
    if (seed) rng_.reseed(*seed);
    t_ = 0;
    return draw();
  }
  rdsim::StepResult step(const rdsim::Action& action) override {
    rdsim::StepResult r;
    r.reward = action.index == side_ ? 1.0f : 0.0f;
    r.truncated = ++t_ >= 10;
    r.observation = draw();
    return r;
  }

private:
  rdsim::Observation draw() {
    side_ = rng_.uniform() < 0.5 ? 0 : 1;
    const int y0 = static_cast<int>(rng_.below(13)), x0 = side_ * 8 + static_cast<int>(rng_.below(5));
    rdsim::Observation o;
    o.pixels.assign(16 * 16 * 3, 0);
    for (int y = y0; y < y0 + 4; ++y)
      for (int x = x0; x < x0 + 4; ++x)
        for (int c = 0; c < 3; ++c) o.pixels[static_cast<size_t>((y * 16 + x) * 3 + c)] = 230;
    return o;
  }

  rdsim::Spec spec_;
  rdsim::Rng rng_;
  int t_ = 0, side_ = 0;
};

std::vector<std::unique_ptr<rdsim::Env>> square_envs(int n) {
  std::vector<std::unique_ptr<rdsim::Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(std::make_unique<SquareSideEnv>());
  return envs;
}

rdsim::AlgorithmConfig pixel_config(const std::string& algorithm) {
  rdsim::AlgorithmConfig c;
  c.params = rdsim::default_algorithm_params(algorithm);
  c.network.cnn.channels = {8};
  c.network.cnn.kernels = {4};
  c.network.cnn.strides = {2};
  c.network.cnn.fc = {32};
  if (auto* ppo = std::get_if<rdsim::PpoConfig>(&c.params)) {
    ppo->n_steps = 64;
    ppo->batch_size = 64;
    ppo->n_epochs = 4;
    ppo->learning_rate = 1e-3;
  }
  if (auto* dqn = std::get_if<rdsim::DqnConfig>(&c.params)) {
    dqn->buffer_size = 1000;
    dqn->learning_starts = 50;
  }
  return c;
}

constexpr std::uint64_t seed = 3;

std::vector<int> greedy_actions(rdsim::Algorithm& algo, int count) {
  SquareSideEnv env;
  rdsim::Rng rng(1);
  std::vector<int> actions;
  rdsim::Observation o = env.reset(7);
  for (int i = 0; i < count; ++i) {
    actions.push_back(algo.act(o, true, rng).index);
    o = env.step(rdsim::Action::discrete(0)).observation;
  }
  return actions;
}

}  // namespace

TEST_CASE("network.cnn: presets by image size, custom stacks, errors name the key", "[algorithms][cnn]") {
  rdsim::ObservationSpace space;
  space.type = rdsim::ObsType::UInt8;
  space.shape = {64, 64, 3};
  rdsim::CnnConfig config;
  CHECK(rdsim::cnn_shape(config, space, 4, "network.cnn").convs == nn::small_cnn({64, 64, 3}, 4).convs);
  space.shape = {84, 84, 6};
  CHECK(rdsim::cnn_shape(config, space, 4, "network.cnn").convs == nn::nature_cnn({84, 84, 6}, 4).convs);
  config.channels = {8, 4};
  config.kernels = {3, 3};
  config.strides = {2, 1};
  config.fc = {10, 20};
  const nn::CnnShape custom = rdsim::cnn_shape(config, space, 4, "network.cnn");
  REQUIRE(custom.convs.size() == 2);
  CHECK(custom.convs[1] == nn::ConvSpec{4, 3, 1, 0});
  CHECK(custom.hidden_sizes == std::vector<int>{10, 20});

  rdsim::Spec spec = SquareSideEnv().spec();
  rdsim::NetworkConfig net;
  net.cnn.channels = {8};
  net.cnn.kernels = {20};  // larger than the 16x16 image
  net.cnn.strides = {1};
  Rng rng(1);
  CHECK_THROWS_WITH(rdsim::ActorCritic(spec, net, rng), Catch::Contains("network.cnn") && Catch::Contains("does not fit"));
  rdsim::AlgorithmConfig dqn = pixel_config("dqn");
  dqn.source = "cfg.json";
  dqn.network.cnn.kernels = {20};
  CHECK_THROWS_WITH(rdsim::make_algorithm(dqn, seed, spec), Catch::Contains("cfg.json: network.cnn"));
}

TEST_CASE("PPO with a CNN policy learns a pixel task, save -> load acts identically", "[algorithms][cnn][ppo]") {
  rdsim::VecEnv vec(square_envs(4), 1);
  const rdsim::AlgorithmConfig config = pixel_config("ppo");
  auto algo = rdsim::make_algorithm(config, seed, vec.spec());
  const long long steps = 8192;
  while (vec.timesteps() < steps) algo->update(vec, {vec.timesteps(), steps});
  const double mean_return = vec.episodes().stats().mean_return;
  INFO("mean return " << mean_return << " (random: 5, best: 10)");
  CHECK(mean_return > 9.0);

  std::stringstream bytes;
  algo->save(bytes, false);
  auto loaded = rdsim::make_algorithm(config, 99, vec.spec());  // different initial weights until loaded
  const std::vector<int> before = greedy_actions(*loaded, 40);
  loaded->load(bytes, false, "model.bin");
  const std::vector<int> actions = greedy_actions(*algo, 40);
  CHECK(greedy_actions(*loaded, 40) == actions);
  CHECK(before != actions);
}

TEST_CASE("A2C and DQN build CNNs for pixels, save -> load acts identically", "[algorithms][cnn]") {
  for (const std::string name : {"a2c", "dqn"}) {
    INFO(name);
    rdsim::VecEnv vec(square_envs(2), 1);
    const rdsim::AlgorithmConfig config = pixel_config(name);
    auto algo = rdsim::make_algorithm(config, seed, vec.spec());
    for (int i = 0; i < 40; ++i) algo->update(vec, {vec.timesteps(), 1000});
    std::stringstream bytes;
    algo->save(bytes, false);
    auto loaded = rdsim::make_algorithm(config, 99, vec.spec());
    loaded->load(bytes, false, "model.bin");
    CHECK(greedy_actions(*loaded, 40) == greedy_actions(*algo, 40));
  }
}
