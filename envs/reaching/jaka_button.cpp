#include "rdsim/envs/reaching/jaka_button.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {

EnvConfig jaka_button_defaults() {
  // max_steps: the paper used 1000 and had no success end.
  EnvConfig c = reach_env_config(EnvConfig{.name = "jaka_button", .max_steps = 200},
                                 ReachOptions{.max_distance = 0.7, .action_step = 0.015, .success_threshold = 0.025,
                                              .ik_iterations = 1});
  c.options.emplace_back(ButtonOptions{});
  return c;
}

// The paper's main camera (yaw 155, pitch -36, fov 60) re-aimed: the paper's target
// (0.316, -0.2, -0.1) and distance 1.6 m put the robot in a corner of the image.
OrbitView reach_main_view() {
  return OrbitView{.target = {0.32f, 0.05f, 0.15f}, .distance = 1.0f, .yaw_deg = 155.0f, .pitch_deg = -36.0f};
}

// The paper's second camera (yaw 32, pitch -13, fov 60; target (0.316, 0.316, -0.105), 1.05 m) re-aimed.
OrbitView reach_second_view() {
  return OrbitView{.target = {0.45f, 0.1f, 0.1f}, .distance = 1.1f, .yaw_deg = 32.0f, .pitch_deg = -13.0f};
}

ReachTaskSpec jaka_button_spec(const EnvConfig& config) {
  const std::string assets = asset_root(config.get<ReachOptions>());
  ReachTaskSpec s;
  s.name = "jaka_button";
  const bool paper = config.get<ButtonOptions>().button == ButtonBody::Paper;
  const Eigen::Isometry3f button(Eigen::Translation3f(0.5f, 0.0f, 0.0f));
  s.statics = {{assets + "/objects/table.urdf", Eigen::Isometry3f(Eigen::Translation3f(0.35f, 0.0f, 0.0f))},
               paper ? StaticBodySpec{assets + "/objects/paper_button.urdf", button, true}
                     : StaticBodySpec{assets + "/objects/button.urdf", button}};
  // The original's floor plane, under a button pushed off the table (collision only, for the button
  // alone: the arm meets the table top, and the floor beyond the table's edges is out of its reach).
  if (paper) s.statics.push_back({assets + "/objects/paper_floor.urdf", s.statics[0].pose, false, true});
  s.target_body = JakaButton::button_index;
  // The original's target is under its button; rdsim's static button is pressed on its top.
  s.target_offset = paper ? Eigen::Vector3f::Zero() : Eigen::Vector3f(0.0f, 0.0f, 0.03f);
  s.nominal_target = button.translation() + s.target_offset;
  s.target_half_range = Eigen::Vector3f(0.15f, 0.3f, 0.0f);
  s.workspace = Eigen::AlignedBox3f(Eigen::Vector3f(0.15f, -0.5f, 0.02f), Eigen::Vector3f(0.85f, 0.5f, 0.55f));
  s.robot_urdf = assets + "/jaka/jaka_zu7.urdf";
  s.ee_link = "flange_link";
  s.home.resize(6);
  s.home << -0.26f, 1.44f, -1.85f, 1.98f, 1.5708f, 0.0f;
  s.rest.resize(6);
  s.rest << 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f;  // RobotDrlSim's reset pose and IK rest pose
  apply_env_config(config, s);
  return s;
}

ReachTerms jaka_button_terms() {
  return ReachTerms{.press_body = JakaButton::button_index,
                    .main_view = reach_main_view(),
                    .second_view = reach_second_view(),
                    .cameras = {jaka_wrist_camera()}};
}

std::unique_ptr<Env> make_jaka_button(const EnvConfig& config) { return std::make_unique<JakaButton>(config); }

}  // namespace rdsim
