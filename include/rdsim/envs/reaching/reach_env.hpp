#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/reaching/obstacle_options.hpp"
#include "rdsim/envs/pixel_view.hpp"
#include "rdsim/envs/task_randomizer.hpp"
#include "rdsim/envs/reaching/reach_task.hpp"
#include "rdsim/envs/robot_cameras.hpp"
#include "rdsim/render/camera.hpp"

// The one Env implementation of every reaching task (jaka_button, jaka_obstacle, inmoov_tomato):
// ReachTask does the physics and IK moves; ReachTerms says what differs between tasks. A task file
// only builds its ReachTaskSpec and ReachTerms.
//
// Episode rules, shared by all reaching tasks (the env options named are ReachOptions', envs/reach_options.hpp):
//   observation   ground truth, observation_layout full: target - end effector (3), end effector -
//                 landmark (3 per landmark), end-effector position (3), then observed link - landmark
//                 (3 per observed link per landmark; none unless a task asks); relative: end effector
//                 - target (3), end effector - landmark (3 per landmark). raw_pixels: the task's
//                 cameras (PixelView). The parts (ObservationSpace::parts): full: target_from_effector,
//                 effector_from_<landmark>..., effector_position, <link>_from_<landmark>...;
//                 relative: effector_from_target, effector_from_<landmark>....
//   reward        negative_distance: -|end effector - target| every step; inverse_distance: see
//                 ReachTerms::reward.
//   collision     any robot link touching the forbidden body: info.collision; negative_distance:
//                 reward = collision_reward and terminated.
//   success       |end effector - target| < success threshold, or the end effector touching the press
//                 body: terminated, info.success (end_on_success); without end_on_success the episode
//                 goes on and info.success says on its last step whether this holds then.
//   out of bounds (workspace_bounds) leaving the workspace box (plus margin) or farther than
//                 max_distance from the target: terminated, info.out_of_bounds, reward
//                 -(max_distance x steps left), so that leaving never pays more than staying.
//   truncation    at the spec's max_steps.
//   walking body  (ReachTerms::walking_body) before each step's move it moves by U(-walk_step,
//                 walk_step) in x and y, staying within walk_range of its place; back there at reset.
// Every reaching env is also a RobotControl (core/robot_control.hpp): move_effector and
// set_joint_targets are env steps judged by the same rules; camera_image draws the terms' cameras
// and "scene", the main view fixed in the world.
namespace rdsim {

struct ReachTerms {
  int press_body = -1;      // index into ReachTaskSpec::statics (-1: none), e.g. the button
  int forbidden_body = -1;  // index into ReachTaskSpec::statics (-1: none), e.g. the column
  float collision_reward = 0.0f;
  // Statics whose base position the observation measures the end effector from (`body`: an index
  // into ReachTaskSpec::statics), and their names in the observation's parts ("effector_from_column").
  struct Landmark {
    int body = -1;
    std::string name;
  };
  std::vector<Landmark> landmarks{};
  // Robot links whose frame origin the observation also measures from each landmark: where the
  // end effector alone does not tell where the rest of the arm is (a wrist offset to one side), and
  // the forbidden body is touched by any link.
  std::vector<std::string> observed_links{};
  // When not empty the target is one of these points (world frame): `default_choice`, or one drawn
  // uniformly at each reset with random_target. Otherwise ReachTaskSpec's nominal point / box decides.
  std::vector<Eigen::Vector3f> target_choices{};
  int default_choice = 0;
  // The scripted expert's way to the target (reach_expert.hpp): world points it passes in order
  // before heading straight for the target; empty = straight there.
  std::vector<Eigen::Vector3f> expert_route{};
  // Then, when not zero, the point target + expert_approach (a pre-grasp point: the side the end
  // effector should arrive from), then the target.
  Eigen::Vector3f expert_approach = Eigen::Vector3f::Zero();
  OrbitView main_view{}, second_view{};  // raw-pixel cameras (second: multi_view)
  // negative_distance: the rules above. inverse_distance (RobotDrlSim's obstacle env): reward
  // 1/max(d, 1 cm) - 2 t / max_steps per step (d = |end effector - target| in m, t = steps taken),
  // -10 on each step touching the forbidden body (the episode goes on), +10 on each step with d < 0.1 m.
  RewardRule reward = RewardRule::NegativeDistance;
  int walking_body = -1;      // index into ReachTaskSpec::statics of a body that random-walks (-1: none)
  float walk_step = 0.003f;   // m, largest move per step and axis
  float walk_range = 0.05f;   // m from its place, per axis
  std::vector<CameraMount> cameras{};  // first-person cameras (RobotControl::camera_image; "scene" is added)
};

class ReachEnv : public Env, public EnvState, public RobotControl {
public:
  ReachEnv(ReachTaskSpec task, ReachTerms terms, const EnvConfig& config);
  ~ReachEnv() override;

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult step(const Action& action) override;
  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed = std::nullopt) override;
  StepOutcome step_into(const Action& action, ObservationOut out) override;
  bool step_physics_only() override;
  bool render(Image& frame) override;
  // Without a renderer (ground truth, no render_mode, no robot cameras drawn yet): nothing of it is
  // bound to a thread. Its steps (microseconds of physics) are long enough to share between
  // workers; the toy envs' (tens of nanoseconds) are not, so they keep the default.
  bool steps_on_any_thread() const override { return !pixels_ && !viewer_ && !cameras_; }

  // EnvState: the task's physics state, the episode's step counter, target choice and random
  // stream; Bullet's contact caches are dropped instead (see core/env_state.hpp).
  std::string save_state() const override;
  void load_state(const std::string& bytes, const std::string& source) override;
  void drop_caches() override { task_->drop_caches(); }

  const RobotInfo& robot_info() const override { return robot_info_; }
  RobotSnapshot robot_state() override;
  StepResult move_effector(const Eigen::Vector3f& position) override;
  StepResult set_joint_targets(const Eigen::VectorXf& targets) override;
  void camera_image(int camera, int width, int height, Image& out) override;

  const ReachTask& task() const { return *task_; }
  ReachTask& task() { return *task_; }
  const ReachTerms& terms() const { return terms_; }
  const PixelView* pixel_view() const { return pixels_.get(); }  // raw-pixel observations only
  int steps() const { return steps_; }
  // Index into terms().target_choices of the current target (-1 without choices).
  int target_index() const { return target_index_; }
  // Makes target_choices[index] the target of the current episode (for evaluation and tests).
  // rdsim::Error when there is no such choice.
  void select_target(int index);

private:
  void observe(ObservationOut out) const;
  // One env step: `set_targets` sets the joint targets, then physics, observation (into `out`)
  // and judge().
  template <class SetTargets>
  StepOutcome control_step(ObservationOut out, SetTargets&& set_targets);
  void judge(StepOutcome& r) const;
  void walk();               // one random-walk step of the walking body
  void place_walking_body();  // puts it at its place + walk_offset_
  // The randomizer's draws of this episode: the target's placement offset (new_episode: a loaded
  // state has it in place already) and the pixel view's camera, colours and light.
  void apply_randomizer(bool new_episode);

  Spec spec_;
  ReachTerms terms_;
  std::unique_ptr<ReachTask> task_;
  std::unique_ptr<PixelView> pixels_;  // raw_pixels only
  std::unique_ptr<PixelView> viewer_;  // render_mode rgb_array only
  std::unique_ptr<RobotCameras> cameras_;  // made on the first camera_image
  std::unique_ptr<TaskRandomizer> randomizer_;  // the config's per-episode randomization (one placement: the target)
  std::string renderer_backend_;
  RobotInfo robot_info_;
  std::vector<Eigen::Vector3f> landmark_points_;
  std::vector<int> observed_links_;  // RobotModel link indices of terms_.observed_links
  Rng rng_;
  ObservationLayout layout_ = ObservationLayout::Full;
  bool end_on_success_ = true;
  Eigen::Vector2f walk_offset_ = Eigen::Vector2f::Zero();  // walking body from its place (x, y)
  bool random_target_ = false;
  int target_index_ = -1;
  int steps_ = 0;
  bool done_ = true;
};

}  // namespace rdsim
