// Policy programs (policy_program.hpp, what `rdsim export` writes as ONNX): for every exportable
// algorithm and network form, run_policy_program() gives the algorithm's own deterministic act() on
// 1,000 observations; the others refuse clearly.
#include <catch2/catch.hpp>

#include "algorithm_setup.hpp"
#include "rdsim/algorithms/policy_program.hpp"
#include "rdsim/core/error.hpp"
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
      {"sac", false, true},  {"td3", false},        {"ddpg", false, true},
  };
  for (const Case& c : cases) {
    INFO(c.algorithm << (c.discrete ? " discrete" : " box") << (c.normalize ? " normalized" : "") << (c.shared ? " shared" : ""));
    rdsim::VecEnv vec(toy::make_envs(2, c.discrete), 4);
    rdsim::AlgorithmConfig config = algorithm_config(setup(c));
    config.normalize_observations = c.normalize;
    auto algo = rdsim::make_algorithm(config, 3, vec.spec());
    while (vec.timesteps() < 300) algo->update(vec, {vec.timesteps(), 300});
    const rdsim::PolicyProgram program = algo->policy_program();
    CHECK(program.discrete == c.discrete);
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
    CHECK(worst <= 1e-6);
  }
}

TEST_CASE("policy programs: the policies that cannot be exported yet say so", "[policy_program]") {
  rdsim::VecEnv vec(toy::make_envs(1, true), 1);
  Setup s;
  s.algorithm = "random";
  CHECK_THROWS_WITH(make_algorithm(s, vec.spec())->policy_program(), Contains("cannot be exported yet"));
}
