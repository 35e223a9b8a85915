// inmoov_tomato (envs/reaching/inmoov_tomato.cpp): the InMoov's right palm reaching a tomato by IK moves.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "env_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/reaching/inmoov_tomato.hpp"
#include "rdsim/envs/registry.hpp"

// Spaces, bounds, determinism and truncation: tests/envs/test_env_contract.cpp.
using rdsim::Action;
using rdsim::EnvConfig;
using rdsim::InmoovTomato;

namespace {

EnvConfig inmoov_config() { return rdsim::test::env_config("inmoov_tomato"); }

// The discrete move that shrinks the largest component of tomato - palm (observation[0..2]).
Action greedy(const rdsim::Observation& o) { return rdsim::test::greedy_action(rdsim::test::to_target(o)); }

}  // namespace

TEST_CASE("inmoov_tomato: six tomatoes, raw pixels, a bad target index", "[envs][inmoov]") {
  EnvConfig pixels = inmoov_config();
  pixels.observation = rdsim::ObservationMode::RawPixels;
  // Raw pixels in detail: tests/envs/test_pixels.cpp.
  CHECK(rdsim::make_env(pixels)->spec().observation.shape == std::vector<int>{64, 64, 3});

  InmoovTomato tomato(inmoov_config());
  CHECK(tomato.tomatoes().size() == 6);
  CHECK(tomato.task().robot().dof() > 50);
  tomato.reset(1);
  CHECK_THROWS_AS(tomato.select_target(6), rdsim::Error);
}

TEST_CASE("inmoov_tomato: reward is minus the palm-tomato distance, other joints hold", "[envs][inmoov]") {
  InmoovTomato env(inmoov_config());
  auto o = env.reset(3);
  CHECK(env.target_index() == InmoovTomato::default_target);
  const auto& task = env.task();
  const Eigen::VectorXf home = task.robot().joint_positions();
  std::vector<int> chain_dofs;
  for (int i = 0; i < task.chain().dof(); ++i) chain_dofs.push_back(task.robot().dof_of_joint(task.chain().model_joint(i)));
  rdsim::Rng rng(5);
  for (int i = 0; i < 60; ++i) {
    const auto r = env.step(Action::discrete(static_cast<int>(rng.below(6))));
    const Eigen::Vector3f palm = task.robot().link_pose(task.ee_link()).translation();
    const Eigen::Vector3f tomato = env.tomatoes()[InmoovTomato::default_target];
    CHECK(r.reward == Approx(-(palm - tomato).norm()).margin(1e-6));
    CHECK(r.observation.values.head<3>().isApprox(tomato - palm, 1e-6f));
    CHECK(r.info.distance == Approx(-r.reward));
    if (r.terminated || r.truncated) break;
  }
  // Head, left arm and fingers keep their home angles (within the drive's tracking error).
  const Eigen::VectorXf q = task.robot().joint_positions();
  for (int d = 0; d < task.robot().dof(); ++d) {
    if (std::find(chain_dofs.begin(), chain_dofs.end(), d) != chain_dofs.end()) continue;
    INFO("dof " << d << " " << task.robot_model().joints[static_cast<size_t>(task.robot().dof_joint(d))].name);
    CHECK(std::abs(q[d] - home[d]) < 0.05f);
  }
}

TEST_CASE("inmoov_tomato: a greedy policy brings the palm to every tomato", "[envs][inmoov]") {
  InmoovTomato env(inmoov_config());
  for (int t = 0; t < static_cast<int>(env.tomatoes().size()); ++t) {
    INFO("tomato_" << t);
    env.reset(static_cast<std::uint64_t>(100 + t));
    env.select_target(t);
    rdsim::Observation obs;
    obs.values.resize(6);
    obs.values << env.task().target() - env.task().ee_position(), env.task().ee_position();
    rdsim::StepResult r;
    int steps = 0;
    while (!r.terminated && !r.truncated) {
      r = env.step(greedy(obs));
      obs = r.observation;
      ++steps;
    }
    CHECK(r.info.success);
    CHECK(r.info.distance < 0.06f);
    CHECK_FALSE(r.info.out_of_bounds);
    // The palm stops at the tomato's skin instead of passing through it.
    CHECK(env.task().world().penetration({env.task().robot().body(), -1},
                                         {env.task().static_body(InmoovTomato::tree_index), -1}) < 0.005f);
    INFO("steps " << steps);
  }
}

TEST_CASE("inmoov_tomato: continuous moves go where they are told", "[envs][inmoov]") {
  EnvConfig c = inmoov_config();
  c.is_discrete = false;
  auto env = rdsim::make_env(c);
  CHECK_FALSE(env->spec().action.discrete);
  CHECK(env->spec().action.dim() == 3);
  const auto start = env->reset(2);
  rdsim::StepResult r;
  for (int i = 0; i < 30; ++i) r = env->step(Action::continuous(Eigen::Vector3f(0.0f, 0.0f, 1.0f)));
  // Palm position is observation[3..5]; 30 moves of 4 mm up.
  const float rise = r.observation.values[5] - start.values[5];
  CHECK(rise > 0.06f);
  CHECK(rise < 0.14f);
  CHECK(std::abs(r.observation.values[3] - start.values[3]) < 0.03f);
}

TEST_CASE("inmoov_tomato: the IK moves only the right arm, the torso holds its pose", "[envs][inmoov]") {
  InmoovTomato env(inmoov_config());
  const auto& task = env.task();
  const auto& model = task.robot_model();
  REQUIRE(task.chain().dof() == 6);
  for (int i = 0; i < task.chain().dof(); ++i)
    CHECK(model.joints[static_cast<size_t>(task.chain().model_joint(i))].name.rfind("r_", 0) == 0);
  const int mid = task.robot().dof_of_joint(model.joint_index("mid_stomach"));
  const int top = task.robot().dof_of_joint(model.joint_index("top_stomach"));
  REQUIRE(mid >= 0);
  REQUIRE(top >= 0);
  const Eigen::Vector3f chest_home = task.robot().link_pose(model.require_link("chest")).translation();
  // Greedy episodes to the highest and the farthest-left tomatoes: the moves that would most
  // tempt an IK with the torso in its chain to lean the body.
  for (int t : {5, 2}) {
    INFO("tomato_" << t);
    auto o = env.reset(40 + static_cast<std::uint64_t>(t));
    env.select_target(t);
    o.values.head<3>() = env.task().target() - env.task().ee_position();
    rdsim::StepResult r;
    float worst = 0.0f;
    while (!r.terminated && !r.truncated) {
      r = env.step(greedy(o));
      o = r.observation;
      const Eigen::VectorXf q = task.robot().joint_positions();
      worst = std::max({worst, std::abs(q[mid] - task.spec().home[mid]), std::abs(q[top] - task.spec().home[top])});
    }
    CHECK(r.info.success);
    // Only the drive's tracking error under the arm's reaction torques.
    CHECK(worst < 0.01f);
    CHECK((task.robot().link_pose(model.require_link("chest")).translation() - chest_home).norm() < 0.005f);
  }
}

TEST_CASE("ReachTask: ik_joints must name movable joints of the robot", "[envs][inmoov]") {
  rdsim::ReachTaskSpec spec = rdsim::inmoov_tomato_spec(inmoov_config());
  spec.ik_joints.push_back("r_no_such_joint");
  try {
    rdsim::ReachTask task(spec);
    FAIL("no error for an unknown ik_joints name");
  } catch (const rdsim::Error& e) {
    CHECK(std::string(e.what()).find("r_no_such_joint") != std::string::npos);
  }
}
