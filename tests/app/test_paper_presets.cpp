// configs/paper/: one training config per paper experiment, resolving to the per-step work and
// task semantics of RobotDrlSim's original envs (issue #17's table; README "Paper presets").
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/training/train_config.hpp"

namespace {

// The resolved "env" object of configs/paper/<name>.json.
nlohmann::json resolved_env(const std::string& name) {
  const rdsim::TrainConfig c = rdsim::read_train_config("configs/paper/" + name + ".json");
  CHECK(c.algorithm.name() == "ppo");
  return rdsim::to_json(c).at("env");
}

}  // namespace

TEST_CASE("paper presets resolve to the original's physics, IK, drive and episode numbers", "[paper]") {
  for (const std::string task : {"jaka_button", "jaka_obstacle", "inmoov_tomato"}) {
    for (const std::string suffix : {"", "_pixels"}) {
      INFO(task + suffix);
      const nlohmann::json env = resolved_env(task + suffix);
      CHECK(env.at("name") == task);
      // Physics per env step: 2 x 1/240 s, 150 solver iterations.
      CHECK(env.at("action_repeat") == 2);
      CHECK(env.at("solver_iterations") == 150);
      // pybullet's null-space IK, 20 iterations, every joint on the way to the end effector, towards
      // the rest pose the episodes start from (Jaka [0,0,1,1,1,1], InMoov all 0), without noise.
      CHECK(env.at("ik_method") == "null_space");
      CHECK(env.at("ik_iterations") == 20);
      CHECK(env.at("ik_joints") == "all");
      CHECK(env.at("reset_pose") == "rest");
      CHECK(env.at("reset_noise") == 0.0);
      // Position motors, force = URDF effort, kp 0.1, kd 1.0, target velocity 0.
      CHECK(env.at("drive") == "position_motor");
      CHECK(env.at("position_gain") == 0.1);
      CHECK(env.at("velocity_gain") == 1.0);
      // Discrete(6) far targets: effector +- 1.0 m (Jaka) / 1.2 m (InMoov) along one axis, no noise,
      // no workspace clip.
      CHECK(env.at("is_discrete") == true);
      CHECK(env.at("action_step") == (task == "inmoov_tomato" ? 1.2 : 1.0));
      CHECK(env.at("move_noise") == 0.0);
      CHECK(env.at("workspace_bounds") == false);
      // 1000 steps (obstacle 250), no success end; success = the default threshold at the last step.
      CHECK(env.at("max_steps") == (task == "jaka_obstacle" ? 250 : 1000));
      CHECK(env.at("end_on_success") == false);
      CHECK(env.at("success_threshold") == (task == "inmoov_tomato" ? 0.06 : 0.025));
      // 3 floats effector - target (obstacle: + effector - column); pixels 224 x 224.
      CHECK(env.at("observation_layout") == "relative");
      CHECK(env.at("observation") == (suffix.empty() ? "ground_truth" : "raw_pixels"));
      if (!suffix.empty()) {
        CHECK(env.at("image_width") == 224);
        CHECK(env.at("image_height") == 224);
        CHECK(env.at("multi_view") == false);
      }
      if (task == "jaka_obstacle") {
        CHECK(env.at("column_motion") == "random_walk");
        CHECK(env.at("reward") == "inverse_distance");
      }
    }
    // A task's two presets differ only in what the agent sees.
    nlohmann::json gt = resolved_env(task), pixels = resolved_env(task + "_pixels");
    for (const char* key : {"observation", "image_width", "image_height"}) {
      gt.erase(key);
      pixels.erase(key);
    }
    CHECK(gt == pixels);
  }
}

TEST_CASE("paper presets: the Jaka button is the paper's fixed button, and random buttons are their own preset", "[paper]") {
  // The paper: "We set a button at a fixed position" (RobotDrlSim's random_target defaults to False).
  CHECK(resolved_env("jaka_button").at("random_target") == false);
  CHECK(resolved_env("jaka_button_pixels").at("random_target") == false);
  nlohmann::json fixed = resolved_env("jaka_button"), random = resolved_env("jaka_button_random");
  CHECK(random.at("random_target") == true);
  fixed.erase("random_target");
  random.erase("random_target");
  CHECK(fixed == random);
}
