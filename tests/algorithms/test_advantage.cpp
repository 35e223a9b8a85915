#include <catch2/catch.hpp>

#include "rdsim/algorithms/advantage.hpp"

using rdsim::EpisodeEnd;
using rdsim::RolloutBuffer;

namespace {

// 4 steps of one env: rewards 1..4, values 0.5..2, the value after the last step 10.
RolloutBuffer four_steps(int envs = 1) {
  RolloutBuffer r;
  r.resize(4, envs, 1, 1);
  for (int t = 0; t < 4; ++t) {
    for (int e = 0; e < envs; ++e) {
      r.rewards[t * envs + e] = static_cast<float>(t + 1);
      r.values[t * envs + e] = 0.5f * static_cast<float>(t + 1);
    }
  }
  r.last_values.setConstant(10.0f);
  return r;
}

}  // namespace

// Hand computation with gamma = lambda = 0.5 (every number exact in float):
//   no end:        deltas 1, 1.75, 2.5, 7 -> advantages 1.703125, 2.8125, 4.25, 7
//   step 1 terminated: delta_1 = 2 - 1 = 1, the trace restarts -> 1.25, 1, 4.25, 7
//   step 1 truncated, V(final obs) = 6: delta_1 = 2 + 3 - 1 = 4 -> 2, 4, 4.25, 7
TEST_CASE("GAE matches a hand-computed case, continuing episode", "[gae]") {
  RolloutBuffer r = four_steps();
  rdsim::compute_gae(r, 0.5f, 0.5f);
  CHECK(r.advantages[0] == 1.703125f);
  CHECK(r.advantages[1] == 2.8125f);
  CHECK(r.advantages[2] == 4.25f);
  CHECK(r.advantages[3] == 7.0f);
  for (int i = 0; i < 4; ++i) CHECK(r.returns[i] == r.advantages[i] + r.values[i]);
}

TEST_CASE("GAE: termination never bootstraps, truncation bootstraps from V(final observation)", "[gae]") {
  RolloutBuffer terminated = four_steps();
  terminated.ends[1] = EpisodeEnd::Terminated;
  terminated.final_values[1] = 6.0f;  // must be ignored
  rdsim::compute_gae(terminated, 0.5f, 0.5f);
  CHECK(terminated.advantages[0] == 1.25f);
  CHECK(terminated.advantages[1] == 1.0f);
  CHECK(terminated.advantages[2] == 4.25f);
  CHECK(terminated.advantages[3] == 7.0f);

  RolloutBuffer truncated = four_steps();
  truncated.ends[1] = EpisodeEnd::Truncated;
  truncated.final_values[1] = 6.0f;
  rdsim::compute_gae(truncated, 0.5f, 0.5f);
  CHECK(truncated.advantages[0] == 2.0f);
  CHECK(truncated.advantages[1] == 4.0f);
  CHECK(truncated.advantages[2] == 4.25f);
  CHECK(truncated.advantages[3] == 7.0f);
}

TEST_CASE("GAE keeps envs apart (sample i = t * envs + e)", "[gae]") {
  RolloutBuffer r = four_steps(2);
  r.ends[1 * 2 + 1] = EpisodeEnd::Terminated;  // env 1 ends at step 1, env 0 continues
  rdsim::compute_gae(r, 0.5f, 0.5f);
  CHECK(r.advantages[0 * 2 + 0] == 1.703125f);
  CHECK(r.advantages[1 * 2 + 0] == 2.8125f);
  CHECK(r.advantages[0 * 2 + 1] == 1.25f);
  CHECK(r.advantages[1 * 2 + 1] == 1.0f);
}

TEST_CASE("GAE with lambda = 1 gives n-step discounted returns", "[gae]") {
  RolloutBuffer r = four_steps();
  rdsim::compute_gae(r, 0.5f, 1.0f);
  // returns_t = r_t + 0.5 r_{t+1} + ... + 0.5^(4-t) * 10
  CHECK(r.returns[3] == 9.0f);
  CHECK(r.returns[2] == 7.5f);
  CHECK(r.returns[1] == 5.75f);
  CHECK(r.returns[0] == 3.875f);

  r.ends[2] = EpisodeEnd::Truncated;
  r.final_values[2] = 2.0f;
  rdsim::compute_gae(r, 0.5f, 1.0f);
  CHECK(r.returns[2] == 4.0f);   // 3 + 0.5 * 2
  CHECK(r.returns[1] == 4.0f);   // 2 + 0.5 * 4
  CHECK(r.returns[3] == 9.0f);   // a new episode
}

TEST_CASE("explained variance", "[gae]") {
  Eigen::VectorXf y(4);
  y << 1, 2, 3, 5;
  CHECK(rdsim::explained_variance(y, y) == Approx(1.0));
  CHECK(rdsim::explained_variance(Eigen::VectorXf::Constant(4, y.mean()), y) == Approx(0.0).margin(1e-12));
  CHECK(rdsim::explained_variance(-y, y) < 0.0);
  CHECK(rdsim::explained_variance(y, Eigen::VectorXf::Constant(4, 2.0f)) == 0.0);
}
