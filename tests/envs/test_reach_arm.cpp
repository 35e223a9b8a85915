// The generic reach env ("reach"): the repo's Jaka URDF used as a user's arm, given by path with
// its effector link, joints, home pose and boxes; the same task rules as the other reaching envs.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "../error_of.hpp"
#include "env_test_util.hpp"
#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/reaching/reach_arm.hpp"
#include "rdsim/envs/reaching/reach_expert.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;
using rdsim::test::error_of;

namespace {

// The Jaka as a user would describe it, over `extra`.
nlohmann::json user_arm(const nlohmann::json& extra = nlohmann::json::object()) {
  nlohmann::json env = {{"name", "reach"},
                        {"urdf", repo_root() + "/assets/jaka/jaka_zu7.urdf"},
                        {"effector_link", "flange_link"},
                        {"joints", {"joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"}},
                        {"home_pose", {-0.26, 1.44, -1.85, 1.98, 1.5708, 0.0}},
                        {"workspace_min", {0.1, -0.5, 0.02}},
                        {"workspace_max", {0.8, 0.5, 0.6}},
                        {"target_centre", {0.45, 0.0, 0.2}},
                        {"target_half_range", {0.15, 0.25, 0.12}},
                        {"random_target", true}};
  env.update(extra);
  return env;
}

EnvConfig read(const nlohmann::json& env) {
  ConfigReader reader(env, "arm.json", "env");
  return read_env_config(reader);
}

std::unique_ptr<Env> make(const nlohmann::json& env) { return make_env(read(env)); }

}  // namespace

TEST_CASE("reach: a user's arm by URDF path has the reaching task's spaces and scene", "[envs][reach_arm]") {
  const EnvConfig config = read(user_arm());
  auto env = make_env(config);
  const Spec& spec = env->spec();
  CHECK(spec.env_name == "reach");
  CHECK(spec.action.discrete);
  CHECK(spec.action.n == 6);
  REQUIRE(spec.observation.shape == std::vector<int>{6});
  const auto& arm = dynamic_cast<ReachArm&>(*env);
  CHECK(arm.task().chain().dof() == 6);
  CHECK(arm.task().spec().statics.size() == 2);  // floor and target marker
  // The target moves with random_target, inside the declared range.
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    env->reset(seed);
    const Eigen::Vector3f t = arm.task().target();
    CHECK(std::abs(t.x() - 0.45f) <= 0.15f + 1e-5f);
    CHECK(std::abs(t.y()) <= 0.25f + 1e-5f);
    CHECK(std::abs(t.z() - 0.2f) <= 0.12f + 1e-5f);
    CHECK(arm.task().world().static_pose(arm.task().static_body(ReachArm::marker_index)).translation().isApprox(t, 1e-5f));
  }
  // Continuous actions and raw pixels as anywhere else.
  nlohmann::json box = user_arm({{"is_discrete", false}, {"observation", "raw_pixels"}, {"image_width", 40},
                                 {"image_height", 32}, {"multi_view", true}});
  auto pixels = make(box);
  CHECK(!pixels->spec().action.discrete);
  CHECK(pixels->spec().observation.shape == std::vector<int>{32, 40, 6});
  const Observation o = pixels->reset(3);
  CHECK(o.pixels.size() == 32u * 40u * 6u);
}

TEST_CASE("reach: the scripted expert's moves bring the user's arm to every target", "[envs][reach_arm]") {
  for (bool discrete : {true, false}) {
    INFO((discrete ? "Discrete" : "Box"));
    auto env = make(user_arm({{"is_discrete", discrete}}));
    ReachExpert expert(*env);
    int successes = 0;
    const int episodes = 10;
    for (int k = 0; k < episodes; ++k) {
      const Observation first = env->reset(900 + static_cast<std::uint64_t>(k));
      expert.reset();
      const float start = test::to_target(first).norm();
      StepResult r;
      for (bool done = false; !done;) {
        r = env->step(expert.act());
        done = r.terminated || r.truncated;
      }
      CHECK(r.info.distance < start);
      successes += r.info.success;
      CHECK(!r.info.out_of_bounds);
    }
    CHECK(successes == episodes);
  }
}

TEST_CASE("reach: the same seed gives the same episode, and the defaults run the repo's Jaka", "[envs][reach_arm]") {
  auto run = [](const EnvConfig& config) {
    auto env = make_env(config);
    std::vector<float> trace;
    Observation o = env->reset(42);
    Rng rng(7);
    for (int t = 0; t < 150; ++t) {
      const StepResult r = env->step(Action::discrete(static_cast<int>(rng.next_u64() % 6)));
      trace.push_back(r.reward);
      for (int i = 0; i < r.observation.values.size(); ++i) trace.push_back(r.observation.values[i]);
      if (r.terminated || r.truncated) o = env->reset();
    }
    return trace;
  };
  const EnvConfig user = read(user_arm());
  CHECK(run(user) == run(user));
  EnvConfig defaults = default_env_config("reach");
  CHECK(arm_urdf(defaults) == asset_root(defaults.get<ReachOptions>()) + "/jaka/jaka_zu7.urdf");
  defaults.get<ReachOptions>().random_target = true;
  CHECK(run(defaults) == run(defaults));
}

TEST_CASE("reach: joints picks the joints the IK moves, the others hold their home values", "[envs][reach_arm]") {
  auto env = make(user_arm({{"joints", {"joint_1", "joint_2", "joint_3"}}, {"home_pose", {-0.26, 1.44, -1.85}}}));
  auto& arm = dynamic_cast<ReachArm&>(*env);
  CHECK(arm.task().chain().dof() == 3);
  // joint_4 .. joint_6 are not controlled: 0 (inside their limits) at home, and they stay there.
  env->reset(1);
  for (int t = 0; t < 30; ++t) env->step(Action::discrete(t % 6));
  const Eigen::VectorXf q = arm.task().robot().joint_positions();
  CHECK(std::abs(q[3]) < 0.05f);
  CHECK(std::abs(q[4]) < 0.05f);
  CHECK(std::abs(q[5]) < 0.05f);
}

TEST_CASE("reach: bad arm options are one clear error naming the file and the key", "[envs][reach_arm]") {
  auto error = [](const nlohmann::json& extra) { return error_of([&] { make(user_arm(extra)); }); };
  const std::string urdf = repo_root() + "/assets/jaka/jaka_zu7.urdf";
  CHECK_THAT(error({{"effector_link", "flange_lnk"}}),
             Contains(urdf + ": env.effector_link: the robot has no link \"flange_lnk\"") && Contains("did you mean \"flange_link\""));
  CHECK_THAT(error({{"joints", {"joint_1", "joint_9"}}}),
             Contains(urdf + ": env.joints: \"joint_9\" is not a joint of the robot") && Contains("joint_1, joint_2"));
  CHECK_THAT(error({{"joints", {"flange_fixed"}}}), Contains("\"flange_fixed\" is not a movable joint on the path"));
  CHECK_THAT(error({{"joints", {"joint_1", "joint_1"}}, {"home_pose", {0.0, 0.0}}}), Contains("\"joint_1\" is listed twice"));
  CHECK_THAT(error({{"home_pose", {0.0, 1.0}}}),
             Contains(urdf + ": env.home_pose: expected 6 values, one per controlled joint (joint_1, joint_2, joint_3, "
                             "joint_4, joint_5, joint_6), got 2"));
  CHECK_THAT(error({{"home_pose", {0.0, 5.0, 0.0, 1.0, 0.0, 0.0}}}),
             Contains("env.home_pose: 5.000000 for joint joint_2 is outside its limits"));
  CHECK_THAT(error({{"target_centre", {0.75, 0.0, 0.2}}}),
             Contains("arm.json: env.target_centre: the target range") && Contains("outside the workspace box"));
  CHECK_THAT(error({{"workspace_min", {0.9, -0.5, 0.02}}}), Contains("arm.json: env.workspace_max: expected each value above"));
  CHECK_THAT(error({{"base_position", {0.0, 0.0}}}), Contains("arm.json: env.base_position: expected 3 numbers"));
  CHECK_THAT(error({{"joints", "joint_1"}}), Contains("arm.json: env.joints: expected a list of at most"));
  CHECK_THAT(error({{"package_paths", {1, 2}}}), Contains("arm.json: env.package_paths: expected a list of at most"));
  CHECK_THAT(error({{"urdf", "/nonexistent/arm.urdf"}}), Contains("/nonexistent/arm.urdf"));
  // A home pose whose effector starts outside the workspace box: every episode would end at once.
  CHECK_THAT(error({{"workspace_min", {0.5, -0.5, 0.02}}, {"target_centre", {0.65, 0.0, 0.2}}, {"target_half_range", {0.1, 0.25, 0.12}}}),
             Contains(urdf + ": env.home_pose puts flange_link at") && Contains("outside the workspace box"));
  CHECK_THAT(error({{"max_distance", 0.0}}), Contains("env.max_distance"));
  // The arm options belong to reach alone.
  CHECK_THAT(error_of([] { read({{"name", "jaka_button"}, {"urdf", "x.urdf"}}); }),
             Contains("env.urdf: has no effect on jaka_button"));
}

TEST_CASE("reach: a config file's relative urdf is relative to the file's folder, recorded absolute", "[envs][reach_arm]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("rdsim_reach_arm_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "robots");
  fs::copy_file(repo_root() + "/assets/jaka/jaka_zu7.urdf", dir / "robots/arm.urdf");
  EnvConfig config = read(user_arm({{"urdf", "robots/arm.urdf"}, {"package_paths", {"robots", "/opt/meshes"}}}));
  resolve_env_paths(config, dir.string());
  const ArmOptions& arm = config.get<ArmOptions>();
  CHECK(arm.urdf == (dir / "robots/arm.urdf").string());
  CHECK(arm.package_paths == std::vector<std::string>{(dir / "robots").string(), "/opt/meshes"});
  CHECK(to_json(config)["urdf"] == (dir / "robots/arm.urdf").string());
  auto env = make_env(config);
  CHECK(dynamic_cast<ReachArm&>(*env).task().spec().package_paths == arm.package_paths);
  fs::remove_all(dir);
}
