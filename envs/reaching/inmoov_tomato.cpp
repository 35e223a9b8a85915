#include "rdsim/envs/reaching/inmoov_tomato.hpp"

#include <cmath>
#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace rdsim {
namespace {

constexpr float kDeg = static_cast<float>(M_PI / 180.0);

// Every joint 0 except the right arm (see the header); one value per robot dof.
Eigen::VectorXf home_pose(const RobotModel& model) {
  Eigen::VectorXf q = Eigen::VectorXf::Zero(model.movable_joint_count());
  int dof = 0;
  for (const Joint& j : model.joints) {
    if (!j.movable()) continue;
    if (j.name == "r_upper_arm_rotate") q[dof] = -30.0f * kDeg;
    // 80, not 90: with the forearm level the fingertips started 2 cm inside tomato_0, and the
    // contact pushed the fingers past their limits on every reset (tests/envs/test_reach_start.cpp).
    if (j.name == "r_elbow") q[dof] = 80.0f * kDeg;
    // Turns the palm's face towards the tree, so the palm centre, not the palm's edge or the fingers,
    // meets the tomato: with wrist roll 0 the edge stops the palm centre 6.5-7 cm from tomatoes 0 and 2.
    if (j.name == "r_wrist_roll") q[dof] = -30.0f * kDeg;
    ++dof;
  }
  return q;
}

}  // namespace

EnvConfig inmoov_tomato_defaults() {
  return reach_env_config(EnvConfig{.name = "inmoov_tomato", .max_steps = 400},
                          ReachOptions{.max_distance = 0.6, .action_step = 0.004, .success_threshold = 0.06,
                                       .ik_iterations = 3});
}

OrbitView inmoov_main_view() {
  return OrbitView{.target = {0.4f, -0.25f, 1.15f}, .distance = 1.2f, .yaw_deg = 120.0f, .pitch_deg = -20.0f};
}

OrbitView inmoov_second_view() {
  return OrbitView{.target = {0.35f, -0.3f, 1.15f}, .distance = 1.1f, .yaw_deg = 15.0f, .pitch_deg = -10.0f};
}

ReachTaskSpec inmoov_tomato_spec(const EnvConfig& config) {
  const std::string assets = asset_root(config.get<ReachOptions>());
  ReachTaskSpec s;
  s.name = "inmoov_tomato";
  s.robot_urdf = assets + "/inmoov/inmoov.urdf";
  s.ee_link = "r_hand_ee";
  // The right arm only: the torso joints on the path to the palm hold their home pose.
  s.ik_joints = {"r_omoplate", "r_shoulder_lift", "r_upper_arm_rotate", "r_elbow", "r_wrist_roll", "r_wrist_pitch"};
  s.home = home_pose(load_urdf(s.robot_urdf));
  s.rest = Eigen::VectorXf::Zero(s.home.size());  // RobotDrlSim's reset pose and IK rest pose: every joint 0
  s.statics = {{assets + "/objects/tomato_tree.urdf", Eigen::Isometry3f(Eigen::Translation3f(0.65f, -0.20f, 0.0f))}};
  s.target_body = -1;  // the tomatoes are part of the tree: the target is set per reset
  s.workspace = Eigen::AlignedBox3f(Eigen::Vector3f(0.10f, -0.70f, 0.80f), Eigen::Vector3f(0.70f, 0.15f, 1.65f));
  apply_env_config(config, s);
  // Not the joint rows' block solve (WorldSettings::joint_block_solve): with it this preset ran
  // slower (4,427-4,518 env steps/s against 6,229-6,259 over 1,000-step runs, the same over
  // 10,000), its light finger joints freed from their welds near the tree keeping the iterations
  // after the direct solve from reaching the residual threshold.
  s.world.joint_block_solve = false;
  // Nor the mass-matrix responses: with its welds the multibody mostly has fewer joints than the
  // model, and the JAKA's measurements do not carry over to a 54-joint tree.
  s.world.mass_matrix_responses = false;
  return s;
}

ReachTerms inmoov_tomato_terms(const ReachTaskSpec& spec) {
  ReachTerms t;
  const StaticBodySpec& tree = spec.statics[InmoovTomato::tree_index];
  const RobotModel model = load_urdf(tree.urdf);
  const auto poses = model.link_poses_at_zero();
  for (int i = 0;; ++i) {
    const int link = model.link_index("tomato_" + std::to_string(i));
    if (link < 0) break;
    t.target_choices.push_back(tree.pose * poses[static_cast<size_t>(link)].translation().cast<float>());
  }
  if (static_cast<int>(t.target_choices.size()) <= InmoovTomato::default_target)
    throw Error(tree.urdf + ": inmoov_tomato needs links tomato_0 .. tomato_" +
                std::to_string(InmoovTomato::default_target) + ", found " + std::to_string(t.target_choices.size()));
  t.default_choice = InmoovTomato::default_target;
  // The scripted expert arrives from 10 cm in front of and 5 cm below the tomato, palm first: straight
  // from the home pose, the fingers met tomatoes 2 and 4 and stopped the palm 6-10 cm short.
  t.expert_approach = Eigen::Vector3f(-0.10f, 0.0f, -0.05f);
  t.main_view = inmoov_main_view();
  t.second_view = inmoov_second_view();
  t.cameras = inmoov_eye_cameras();
  return t;
}

std::unique_ptr<Env> make_inmoov_tomato(const EnvConfig& config) { return std::make_unique<InmoovTomato>(config); }

}  // namespace rdsim
