// Every reaching env starts each episode with the robot clear of the scene. A start pose inside a
// static body (the InMoov's fingers once began inside a tomato) makes the solver push joints past
// their limits and jitter there, which no policy asked for and which slows every physics step.
#include <catch2/catch.hpp>
#include <string>
#include <utility>
#include <vector>

#include "env_test_util.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;

namespace {

// Robot links other than the root (which stands on the table or floor) that touch static body `s`.
std::string links_touching(const ReachTask& task, int s) {
  std::string out;
  const int robot = task.robot().body();
  const RobotModel& model = task.robot_model();
  for (int link = 1; link < static_cast<int>(model.links.size()); ++link)
    if (task.world().touching({robot, link}, {task.static_body(s), -1})) out += model.links[static_cast<size_t>(link)].name + " ";
  return out;
}

// Joints farther than `tolerance` outside their URDF limits.
std::string joints_outside_limits(const ReachTask& task, float tolerance) {
  std::string out;
  const Robot& robot = task.robot();
  for (int dof = 0; dof < robot.dof(); ++dof) {
    const Joint& j = task.robot_model().joints[static_cast<size_t>(robot.dof_joint(dof))];
    const double q = robot.joint_position(dof);
    if (q < j.lower - tolerance || q > j.upper + tolerance) out += j.name + "=" + std::to_string(q) + " ";
  }
  return out;
}

}  // namespace

TEST_CASE("reaching envs: the robot starts clear of the scene and holds its pose inside its limits", "[envs]") {
  // Each env with its defaults and with its paper preset (RobotDrlSim's rest pose, position motors).
  std::vector<std::pair<std::string, EnvConfig>> cases;
  for (const std::string name : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    cases.emplace_back(name, test::env_config(name, /*random_target=*/true));
    cases.emplace_back(name + " paper preset", test::paper_env_config(name));
  }
  cases.emplace_back("reach", test::env_config("reach", /*random_target=*/true));
  for (const auto& [label, config] : cases) {
    auto env = make_env(config);
    auto& reach = dynamic_cast<ReachEnv&>(*env);
    const ReachTask& task = reach.task();
    for (std::uint64_t seed = 0; seed < 10; ++seed) {
      INFO(label << " seed " << seed);
      env->reset(seed);
      for (int k = 0; k < 240; ++k) env->step_physics_only();  // one simulated second (or two), holding still
      for (int s = 0; s < static_cast<int>(task.spec().statics.size()); ++s) {
        INFO("static body " << task.spec().statics[static_cast<size_t>(s)].urdf);
        CHECK(links_touching(task, s) == "");
      }
      CHECK(joints_outside_limits(task, 0.01f) == "");
    }
  }
}
