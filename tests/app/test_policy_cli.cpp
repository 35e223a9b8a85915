// rdsim_policy (issue #43 item 4) on models that `rdsim train` wrote: the Policy a controller loads
// gives the actions the trained algorithm takes (what `rdsim replay` runs) on the env's own
// observations, for a discrete and a continuous goal policy, from model.bin and checkpoint.bin; the
// example program prints them; unusable files and bad observations are one clear error. The file
// format alone: tests/policy; that the library links no simulation or training code: the ctest
// "policy: the example links rdsim_policy ..." (tests/policy/links_alone.cmake).
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include "rdsim/envs/registry.hpp"
#include "rdsim/policy/policy.hpp"
#include "rdsim/training/saved_policy.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::run_captured;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

// PPO on jaka_button with normalised observations (discrete) and SAC + HER on reach_goal (a goal
// env's flat observation, squashed Gaussian), each a few seconds.
const char* ppo_text = R"({"algorithm": "ppo", "env": {"name": "jaka_button", "random_target": true}, "seed": 3,
  "total_timesteps": 4096, "num_envs": 4, "normalize_observations": true, "checkpoint_interval": 2048,
  "network": {"hidden_sizes": [32, 32]}, "ppo": {"n_steps": 256, "batch_size": 256}})";
const char* sac_text = R"({"algorithm": "sac", "env": {"name": "reach_goal", "max_steps": 20}, "seed": 4,
  "total_timesteps": 1200, "num_envs": 2, "network": {"hidden_sizes": [32, 32]},
  "sac": {"learning_starts": 200, "batch_size": 64, "buffer_size": 2000}, "her": {}})";

std::string train(const ScratchDir& dir, const std::string& name, const char* text) {
  const std::string config = dir / (name + ".json"), run = dir / name;
  rltest::spit(config, text);
  const auto r = run_rdsim("train --quiet --config " + config + " --log-dir " + run, dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return run;
}

// Observations of the model's env over `steps` steps, driven by the policy itself (so they are the
// states a controller meets), with the Policy's and the trained algorithm's action for each.
struct Compared {
  std::vector<rdsim::Observation> observations;
  int differ = 0;       // discrete actions that differ
  double worst = 0.0;   // continuous: the largest |difference|
};

Compared compare(const std::string& model, int steps) {
  const rdsim::Policy policy = rdsim::Policy::load(model);
  rdsim::SavedPolicy saved = rdsim::load_saved_policy(model);
  CHECK(policy.env_spec() == rdsim::describe_spec(saved.spec));
  auto env = rdsim::make_env(saved.config.env);
  rdsim::Rng unused(0);
  Compared c;
  std::uint64_t seed = 1;
  rdsim::Observation obs = env->reset(seed);
  for (int t = 0; t < steps; ++t) {
    const rdsim::Action mine = policy.act(obs);
    const rdsim::Action theirs = saved.algorithm->act(obs, true, unused);
    if (policy.discrete())
      c.differ += mine.index != theirs.index;
    else
      c.worst = std::max(c.worst, static_cast<double>((mine.values - theirs.values).cwiseAbs().maxCoeff()));
    c.observations.push_back(obs);
    const rdsim::StepResult s = env->step(mine);
    obs = s.terminated || s.truncated ? env->reset(++seed) : s.observation;
  }
  return c;
}

}  // namespace

TEST_CASE("rdsim_policy: a trained model's policy acts as the trained algorithm on the env's observations",
          "[cli][policy]") {
  ScratchDir dir("policy_acts");
  const std::string ppo = train(dir, "ppo", ppo_text);
  for (const std::string file : {"/model.bin", "/checkpoint.bin"}) {
    INFO(file);
    const Compared c = compare(ppo + file, 1000);
    CHECK(c.differ == 0);
  }
  const std::string sac = train(dir, "sac", sac_text);
  const Compared c = compare(sac + "/model.bin", 1000);
  CHECK(c.worst <= 1e-5);
  const rdsim::Policy policy = rdsim::Policy::load(sac + "/model.bin");
  CHECK(policy.algorithm() == "sac");
  CHECK_FALSE(policy.discrete());
}

TEST_CASE("rdsim_policy: the example prints the policy's actions for observations on its input", "[cli][policy]") {
  ScratchDir dir("policy_example");
  const std::string run = train(dir, "ppo", ppo_text);
  const Compared c = compare(run + "/model.bin", 50);
  const rdsim::Policy policy = rdsim::Policy::load(run + "/model.bin");
  std::ostringstream input, expected;
  input.precision(9);  // float values survive the text round trip
  for (const rdsim::Observation& o : c.observations) {
    for (Eigen::Index k = 0; k < o.values.size(); ++k) input << (k ? " " : "") << o.values[k];
    input << "\n";
    expected << policy.act(o).index << "\n";
  }
  rltest::spit(dir / "observations.txt", input.str());
  const auto r = run_captured(RDSIM_POLICY_EXAMPLE, run + "/model.bin < " + (dir / "observations.txt"), dir);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out == expected.str());
  CHECK_THAT(r.err, Contains("ppo policy for jaka_button: observation float32"));
  rltest::spit(dir / "short.txt", "0.5 0.5\n");
  const auto bad = run_captured(RDSIM_POLICY_EXAMPLE, run + "/model.bin < " + (dir / "short.txt"), dir);
  CHECK(bad.exit_code == 1);
  CHECK_THAT(bad.err, Contains("observation has 2 values"));
  CHECK(run_captured(RDSIM_POLICY_EXAMPLE, "", dir).exit_code == 2);
}

TEST_CASE("rdsim_policy: a random agent's model and a damaged file are one clear error", "[cli][policy]") {
  ScratchDir dir("policy_errors");
  const std::string config = dir / "random.json";
  rltest::spit(config, R"({"algorithm": "random", "env": {"name": "jaka_button"}, "total_timesteps": 200, "num_envs": 1,
    "random": {"n_steps": 100}})");
  REQUIRE(run_rdsim("train --quiet --config " + config + " --log-dir " + (dir / "random"), dir).exit_code == 0);
  CHECK_THROWS_WITH(rdsim::Policy::load(dir / "random/model.bin"), Contains("has no policy to run"));
  const std::string run = train(dir, "ppo", ppo_text);
  std::string bytes = rltest::slurp(run + "/model.bin");
  bytes[bytes.size() / 2] ^= 0x10;
  rltest::spit(dir / "damaged.bin", bytes);
  CHECK_THROWS_WITH(rdsim::Policy::load(dir / "damaged.bin"), Contains("damaged.bin: file is damaged (checksum mismatch)"));
  const auto r = run_captured(RDSIM_POLICY_EXAMPLE, dir / "damaged.bin", dir);
  CHECK(r.exit_code == 1);
  CHECK(rltest::lines(r.err).size() == 1);
}
