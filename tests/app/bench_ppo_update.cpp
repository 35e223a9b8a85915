// Manual benchmark, hidden from the default run (tag starts with "."):
//   ./build/test_app "[.bench]"
// Wall-clock and CPU time of one PPO update (rollout + epochs of minibatches) with the shipped
// jaka_button configs: what -march=native (RDSIM_NATIVE) changes. Compare two builds' output.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <vector>

#include "rdsim/algorithms/actor_critic.hpp"
#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/envs/registry.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void bench_config(const std::string& path, int updates) {
  const rdsim::TrainConfig c = rdsim::read_train_config(std::string(RDSIM_SOURCE_DIR) + "/" + path);
  std::vector<std::unique_ptr<rdsim::Env>> envs;
  for (int i = 0; i < c.num_envs; ++i) envs.push_back(rdsim::make_env(c.env));
  rdsim::VecEnv vec(std::move(envs), c.seed, c.stats_window, 1);
  auto algo = rdsim::make_algorithm(c.algorithm, c.seed, vec.spec());
  const long long total = 1'000'000'000;
  algo->update(vec, {vec.timesteps(), total});  // warm-up
  std::vector<double> wall, cpu;
  long long steps = 0;
  for (int u = 0; u < updates; ++u) {
    const long long before = vec.timesteps();
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    algo->update(vec, {vec.timesteps(), total});
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    steps = vec.timesteps() - before;
  }
  std::printf("%-32s PPO update (%lld env steps + training): median of %d: %.1f ms wall, %.1f ms CPU\n",
              path.c_str(), steps, updates, 1e3 * median(wall), 1e3 * median(cpu));

  // The network part alone: forward, backward and Adam step on minibatches of the config's size.
  const auto& ppo = std::get<rdsim::PpoConfig>(c.algorithm.params);
  rdsim::Rng rng(1);
  rdsim::ActorCritic policy(vec.spec(), c.algorithm.network, rng);
  rdsim::nn::Adam adam(policy.params());
  const int b = ppo.batch_size;
  Eigen::MatrixXf obs = Eigen::MatrixXf::Random(policy.observation_size(), b).cwiseAbs();
  Eigen::MatrixXf actions = Eigen::MatrixXf::Zero(policy.action_dim(), b);
  const Eigen::VectorXf d = Eigen::VectorXf::Constant(b, 1.0f / static_cast<float>(b));
  const int minibatches = ppo.n_epochs * std::max(1, ppo.n_steps * c.num_envs / b);
  std::vector<double> train_wall, train_cpu;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    for (int m = 0; m < minibatches; ++m) {
      policy.evaluate(obs, actions);
      policy.zero_grad();
      policy.backward(d, d, d);
      adam.step();
    }
    train_cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    train_wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("%-32s network only (%d minibatches of %d: forward, backward, Adam): median of 5: %.1f ms wall, "
              "%.1f ms CPU\n", path.c_str(), minibatches, b, 1e3 * median(train_wall), 1e3 * median(train_cpu));
}

}  // namespace

TEST_CASE("PPO update time of the shipped jaka_button configs", "[.bench]") {
  bench_config("configs/jaka_button.json", 15);
  bench_config("configs/jaka_button_pixels.json", 5);
}
