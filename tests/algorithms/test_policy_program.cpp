// Policy programs (policy/policy_program.hpp, what `rdsim export` writes as ONNX and model files
// carry for rdsim_policy): for every exportable algorithm and network form, run_policy_program()
// gives the algorithm's own deterministic act() on 1,000 observations after a round trip through
// the policy file format (policy/policy_file.hpp); the others refuse clearly.
#include <catch2/catch.hpp>

#include "algorithm_setup.hpp"
#include "rdsim/policy/policy_file.hpp"
#include "rdsim/policy/policy_program.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/vecenv/observation_batch.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "toy_env.hpp"

using Catch::Matchers::Contains;

namespace {

struct Case {
  std::string algorithm;
  bool discrete;
  bool normalize = false;
  bool shared = false;
  double input_scale = 1.0;
};

// The program as a model file carries it: encoded, decoded, and encoded again to the same bytes.
rdsim::PolicyProgram round_trip(const rdsim::PolicyProgram& program) {
  const std::string bytes = rdsim::encode_policy_program(program);
  rdsim::PolicyProgram back = rdsim::decode_policy_program(bytes, "policy");
  CHECK(rdsim::encode_policy_program(back) == bytes);
  return back;
}

Setup setup(const Case& c) {
  Setup s = small_setup(c.algorithm, 3);
  s.network.shared = c.shared;
  s.network.input_scale = c.input_scale;
  return s;
}

}  // namespace

TEST_CASE("policy programs give every exportable algorithm's deterministic actions", "[policy_program]") {
  const std::vector<Case> cases = {
      {"ppo", true},         {"ppo", false},        {"ppo", false, true},      {"a2c", true, false, true},
      {"trpo", false, false, false, 0.5}, {"dqn", true}, {"dqn", true, true}, {"sac", false},
      {"sac", false, true},  {"td3", false},        {"ddpg", false, true}, {"ars", true}, {"ars", false},
      {"cma_es", false},
  };
  for (const Case& c : cases) {
    INFO(c.algorithm << (c.discrete ? " discrete" : " box") << (c.normalize ? " normalized" : "") << (c.shared ? " shared" : ""));
    rdsim::VecEnv vec(toy::make_envs(2, c.discrete), 4);
    rdsim::AlgorithmConfig config = algorithm_config(setup(c));
    config.normalize_observations = c.normalize;
    auto algo = rdsim::make_algorithm(config, 3, vec.spec());
    while (vec.timesteps() < 300) algo->update(vec, {vec.timesteps(), 300});
    const rdsim::PolicyProgram program = round_trip(algo->policy_program());
    CHECK(program.discrete == c.discrete);
    CHECK(program.algorithm == c.algorithm);
    rdsim::Rng rng(11), unused(0);
    Eigen::MatrixXf x(2, 1000);
    for (Eigen::Index k = 0; k < x.size(); ++k) x.data()[k] = static_cast<float>(rng.normal());
    const Eigen::MatrixXf y = rdsim::run_policy_program(program, x);
    REQUIRE(y.cols() == 1000);
    int differ = 0;
    double worst = 0.0;
    for (int i = 0; i < 1000; ++i) {
      rdsim::Observation o;
      o.values = x.col(i);
      const rdsim::Action a = algo->act(o, true, unused);
      if (c.discrete)
        differ += a.index != static_cast<int>(y(0, i));
      else
        worst = std::max(worst, static_cast<double>((a.values - y.col(i)).cwiseAbs().maxCoeff()));
    }
    CHECK(differ == 0);
    CHECK(worst <= (c.algorithm == "ars" || c.algorithm == "cma_es" ? 1e-5 : 1e-6));  // their statistics are in double
  }
}

TEST_CASE("policy programs give CNN policies' deterministic actions on pixel observations", "[policy_program]") {
  for (const std::string name : {"ppo", "dqn"}) {
    INFO(name);
    std::vector<std::unique_ptr<rdsim::Env>> envs;
    for (int i = 0; i < 2; ++i) envs.push_back(std::make_unique<toy::Corridor>(true));
    rdsim::VecEnv vec(std::move(envs), 4);
    Setup s = small_setup(name, 5);
    s.network.cnn.channels = {4};
    s.network.cnn.kernels = {3};
    s.network.cnn.strides = {1};
    s.network.cnn.fc = {16};
    auto algo = make_algorithm(s, vec.spec());
    while (vec.timesteps() < 200) algo->update(vec, {vec.timesteps(), 200});
    const rdsim::PolicyProgram program = round_trip(algo->policy_program());
    CHECK(program.pixels);
    CHECK(program.image_shape == vec.spec().observation.shape);
    rdsim::Rng rng(12), unused(0);
    const int size = vec.spec().observation.size();
    Eigen::MatrixXf x(size, 300);
    std::vector<rdsim::Observation> observations(300);
    for (int i = 0; i < 300; ++i) {
      observations[static_cast<std::size_t>(i)].pixels.resize(static_cast<std::size_t>(size));
      for (auto& p : observations[static_cast<std::size_t>(i)].pixels) p = static_cast<std::uint8_t>(rng.below(256));
      rdsim::encode_observation(observations[static_cast<std::size_t>(i)], vec.spec().observation, x.col(i));
    }
    const Eigen::MatrixXf y = rdsim::run_policy_program(program, x);
    int differ = 0;
    for (int i = 0; i < 300; ++i) differ += algo->act(observations[static_cast<std::size_t>(i)], true, unused).index != static_cast<int>(y(0, i));
    CHECK(differ == 0);
  }
}

TEST_CASE("policy programs: the random agent has no policy to export", "[policy_program]") {
  rdsim::VecEnv vec(toy::make_envs(1, true), 1);
  Setup s;
  s.algorithm = "random";
  auto algo = make_algorithm(s, vec.spec());
  CHECK_FALSE(algo->has_policy_program());
  CHECK_THROWS_WITH(algo->policy_program(), Contains("no policy to export"));
}
