#include "rdsim/envs/jaka_button.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

Eigen::Isometry3f at(float x, float y, float z) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translation() << x, y, z;
  return t;
}

}  // namespace

EnvConfig jaka_button_defaults() {
  EnvConfig c;
  c.name = "jaka_button";
  c.max_steps = 200;  // the paper used 1000 and had no success end
  c.action_step = 0.015;
  c.success_threshold = 0.025;
  c.max_distance = 0.7;
  c.action_repeat = 1;
  return c;
}

ReachTaskSpec jaka_button_spec(const EnvConfig& config) {
  const std::string assets = asset_root(config);
  ReachTaskSpec s;
  s.robot_urdf = assets + "/jaka/jaka_zu7.urdf";
  s.ee_link = "flange_link";
  s.home.resize(6);
  s.home << -0.26f, 1.44f, -1.85f, 1.98f, 1.5708f, 0.0f;
  s.home_noise = 0.02f;
  s.statics = {{assets + "/objects/table.urdf", at(0.35f, 0.0f, 0.0f)},
               {assets + "/objects/button.urdf", at(0.5f, 0.0f, 0.0f)}};
  s.target_body = JakaButton::button_index;
  s.target_offset = Eigen::Vector3f(0.0f, 0.0f, 0.03f);  // the top of the button
  s.nominal_target = Eigen::Vector3f(0.5f, 0.0f, 0.03f);
  s.target_half_range = Eigen::Vector3f(0.15f, 0.3f, 0.0f);
  s.workspace = Eigen::AlignedBox3f(Eigen::Vector3f(0.15f, -0.5f, 0.02f), Eigen::Vector3f(0.85f, 0.5f, 0.55f));
  s.move_noise = 1.0f / 30.0f;
  s.workspace_margin = 0.03f;
  s.ik_iterations = 1;
  s.world.time_step = 1.0 / 240.0;
  s.world.solver_iterations = 10;
  s.robot.drive = JointDrive::ComputedTorque;
  s.robot.limit_constraints = false;
  apply_env_config(config, s);
  return s;
}

ReachTerms jaka_button_terms() {
  ReachTerms t;
  t.env_name = "jaka_button";
  t.press_body = JakaButton::button_index;
  t.main_view = reach_main_view();
  t.second_view = reach_second_view();
  t.cameras = {jaka_wrist_camera()};
  return t;
}

std::unique_ptr<Env> make_jaka_button(const EnvConfig& config) { return std::make_unique<JakaButton>(config); }

}  // namespace rdsim
