#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/core/scene_redraw.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/manipulation/manipulation_options.hpp"
#include "rdsim/envs/manipulation/manipulation_task.hpp"
#include "rdsim/envs/pixel_view.hpp"
#include "rdsim/envs/robot_cameras.hpp"
#include "rdsim/envs/task_randomizer.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"

// A goal-conditioned manipulation env (Gymnasium-Robotics' GoalEnv, panda-gym's conventions): an
// arm with a gripper (ArmOptions, ManipulationOptions::finger_joints), a table, the task's 4 cm cubes, and a goal each episode
// (ManipulationTask). Spec::goal declares the observation's three slices and the reward.
//
// Scene (world frame, z up, metres): the table top is the plane z = 0 (assets/objects/table.urdf,
// 1.2 m square, centred 0.35 m in front of the origin), a floor 0.75 m below catches what falls off;
// the robot's root at base_position; cubes (assets/objects/cube_blue.urdf, cube_green.urdf: 4 cm,
// 0.1 kg) are free bodies; goals are drawn as spheres nothing collides with.
//
// Actions: Box(4) in [-1, 1]: dx, dy, dz (times effector_step, metres: the effector's goal for this
// step, reached by two IK steps that also hold the home pose's gripper orientation, goals
// clipped into the workspace box) and the fingers' opening (-1 closed, 1 fully open: each finger's
// target is the matching share of its stroke; the fingers close with at most their URDF effort, so
// the grip force is the effort). block_gripper: Box(3), the fingers held closed. Non-finite values
// count as 0, others are clipped to [-1, 1]. control "joints": one value per arm joint (the IK
// chain's, ReachTask::chain_dofs) instead of dx, dy, dz: that joint's target is its position plus
// the value times joint_step (rad), clamped to its limits; the fingers' value follows as before.
//
// Observation (Float32, ground truth), in this order:
//   observation: effector position (3), effector velocity (3, m/s), finger opening (1, m; without
//                block_gripper), joint positions (control "joints": one per arm joint, rad), then per cube: position (3), orientation (4: quaternion x, y, z, w
//                with w >= 0), linear velocity (3), angular velocity (3), position - effector (3);
//   achieved_goal: each cube's position (3 each; reach_goal: the effector's);
//   desired_goal: the goal points (as many).
// Its parts (ObservationSpace::parts), in that order: effector_position, effector_velocity,
// finger_opening, joint_positions (control "joints"), then cube1_position, cube1_orientation, cube1_velocity, cube1_angular_velocity,
// cube1_from_effector (cube2_... for a second cube), achieved_goal, desired_goal.
// Every value is clipped into the space's bounds (a cube fallen to the floor still fits).
// Observation "raw_pixels": the camera image (PixelView: the arm's main view, or both with
// multi_view; image_channels as for the reach tasks) with the achieved and desired goals beside it
// (pixel_goal_space): Python's Dict observation holds the image as "observation".
// Reward and success: Spec::goal (core/goal_layout.hpp) with reward_type and distance_threshold;
// info.success = every goal point within distance_threshold; info.distance = |achieved - desired|.
// Episodes: max_steps steps (50; stack 100, as panda-gym's); success ends one (terminated, panda-gym's rule).
// RobotControl (core/robot_control.hpp), as the reaching envs: move_effector (IK holding the gripper's
// orientation; the fingers keep their targets), set_joint_targets (every joint, the fingers too: the
// gripper by hand), the "scene" camera; robot_state's target is the first goal.
// SceneRedraw (core/scene_redraw.hpp): the cubes still where the reset put them, and the goal unless
// a cube (reach_goal: the effector) is on its point, drawn again as the task's reset draws them,
// each cube at least 1.5 cube edges from the others and 10 cm from the effector (in x and y).
namespace rdsim {

class ManipulationEnv : public Env, public EnvState, public RobotControl, public SceneRedraw {
public:
  // rdsim::Error naming the URDF file and key for a robot that does not fit (see gripper_arm.hpp).
  ManipulationEnv(const ManipulationTask& task, const EnvConfig& config);
  ~ManipulationEnv() override;

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult step(const Action& action) override;
  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed = std::nullopt) override;
  StepOutcome step_into(const Action& action, ObservationOut out) override;
  bool step_physics_only() override;
  bool render(Image& frame) override;
  bool steps_on_any_thread() const override { return !pixels_ && !viewer_ && !cameras_; }

  const RobotInfo& robot_info() const override { return robot_info_; }
  RobotSnapshot robot_state() override;
  StepResult move_effector(const Eigen::Vector3f& position) override;
  StepResult set_joint_targets(const Eigen::VectorXf& targets) override;
  void camera_image(int camera, int width, int height, Image& out) override;

  std::string save_state() const override;
  void load_state(const std::string& bytes, const std::string& source) override;
  void drop_caches() override { world_->drop_caches(); }

  bool redraw_unmoved(Rng& rng, ObservationOut out) override;

  // For the scripted expert and tests: privileged state.
  const ManipulationTask& task() const { return task_; }
  const ReachTask& world() const { return *world_; }
  ReachTask& world() { return *world_; }
  int cubes() const { return task_.cubes; }
  Eigen::Vector3f cube_position(int cube) const;
  const std::vector<Eigen::Vector3f>& goals() const { return goals_; }
  float finger_opening() const;        // m
  float finger_stroke() const { return stroke_; }  // m: the widest opening
  bool gripper_blocked() const { return blocked_; }
  float effector_step() const { return effector_step_; }
  ArmControl control() const { return control_; }
  float joint_step() const { return joint_step_; }  // rad per unit action (control: joints)
  int steps() const { return steps_; }

  // Where the statics of the scene sit in ReachTaskSpec::statics.
  static constexpr int table_index = 0, floor_index = 1, first_cube_index = 2;

private:
  // One env step: `set_targets` sets the joint targets, then physics, observation (into `out`) and
  // judge(); after the episode's end nothing moves (core/env.hpp).
  template <class SetTargets>
  StepOutcome control_step(ObservationOut out, SetTargets&& set_targets);
  void observe(ObservationOut out) const;
  // The achieved and desired goals into `values` at Spec::goal's offsets, clipped into their bounds.
  void observe_goals(float* values) const;
  void achieved_goal(float* out) const;
  void judge(const float* observation, StepOutcome& r) const;
  void place(const Placement& placement);
  void show_goals();  // the goal markers to goals_
  std::vector<bool> unmoved_cubes() const;  // per cube: still where the reset put it (to 1 mm)
  bool goal_point_reached() const;          // some goal point within distance_threshold
  // This episode's placement drawn from `rng` as the reset draws it (with the randomizer's offsets).
  Placement draw_placement(Rng& rng) const;
  void set_opening(float opening);  // finger targets for this opening (m)

  const ManipulationTask& task_;
  Spec spec_;
  std::unique_ptr<ReachTask> world_;
  std::unique_ptr<PixelView> pixels_;  // observation raw_pixels only
  std::unique_ptr<PixelView> viewer_;  // render_mode rgb_array only
  std::vector<CameraMount> camera_mounts_;  // RobotControl's cameras: the scene camera
  std::unique_ptr<RobotCameras> cameras_;   // made on the first camera_image
  // The config's per-episode randomization; two placements: all cubes by one offset (they keep
  // apart), all goals by another (a stack's goals stay stacked).
  std::unique_ptr<TaskRandomizer> randomizer_;
  std::string renderer_backend_;
  RobotInfo robot_info_;
  TaskArea area_;
  std::vector<int> finger_dofs_;
  std::vector<float> finger_lower_, finger_share_;  // per finger: lower limit, share of the stroke
  float stroke_ = 0.0f;
  bool blocked_ = false;
  float effector_step_ = 0.05f;
  ArmControl control_ = ArmControl::Effector;
  float joint_step_ = 0.05f;
  std::vector<Eigen::Vector3f> goals_;
  // Where the cubes stood after the reset (redraw_unmoved's "not moved"); empty after load_state,
  // which does not record it (nothing counts as unmoved then).
  std::vector<Eigen::Vector3f> placed_;
  Rng rng_;
  int steps_ = 0;
  bool done_ = true;
};

// The registry's entries: each task's defaults and maker (envs/manipulation/<task>.cpp).
EnvConfig push_defaults();
EnvConfig pick_and_place_defaults();
EnvConfig stack_defaults();
EnvConfig reach_goal_defaults();
std::unique_ptr<Env> make_push(const EnvConfig& config);
std::unique_ptr<Env> make_pick_and_place(const EnvConfig& config);
std::unique_ptr<Env> make_stack(const EnvConfig& config);
std::unique_ptr<Env> make_reach_goal(const EnvConfig& config);

// The defaults every manipulation task starts from (50 steps, Box actions, both option groups) with
// the task's own ManipulationOptions.
EnvConfig manipulation_env_config(const std::string& name, ManipulationOptions options);

}  // namespace rdsim
