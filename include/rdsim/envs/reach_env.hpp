#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/envs/pixel_view.hpp"
#include "rdsim/envs/reach_task.hpp"
#include "rdsim/render/camera.hpp"

// The one Env implementation of every reaching task (jaka_button, jaka_obstacle, inmoov_tomato):
// ReachTask does the physics and IK moves; ReachTerms says what differs between tasks. A task file
// only builds its ReachTaskSpec and ReachTerms.
//
// Episode rules, shared by all reaching tasks:
//   observation   ground truth: target - end effector (3), end effector - landmark (3 per landmark),
//                 end-effector position (3), then observed link - landmark (3 per observed link per
//                 landmark; none unless a task asks); raw_pixels: the task's cameras (PixelView).
//   reward        -|end effector - target| every step.
//   collision     any robot link touching the forbidden body: reward = collision_reward, terminated,
//                 info.collision.
//   success       |end effector - target| < success threshold, or the end effector touching the press
//                 body: terminated, info.success.
//   out of bounds leaving the workspace box (plus margin) or farther than max_distance from the target:
//                 terminated, info.out_of_bounds, reward -(max_distance x steps left), so that leaving
//                 never pays more than staying.
//   truncation    at the spec's max_steps.
namespace rdsim {

struct ReachTerms {
  int press_body = -1;      // index into ReachTaskSpec::statics (-1: none), e.g. the button
  int forbidden_body = -1;  // index into ReachTaskSpec::statics (-1: none), e.g. the column
  float collision_reward = 0.0f;
  std::vector<int> landmarks{};  // statics whose base position the observation measures the end effector from
  // Robot links whose frame origin the observation also measures from each landmark: where the
  // end effector alone does not tell where the rest of the arm is (a wrist offset to one side), and
  // the forbidden body is touched by any link.
  std::vector<std::string> observed_links{};
  // When not empty the target is one of these points (world frame): `default_choice`, or one drawn
  // uniformly at each reset with random_target. Otherwise ReachTaskSpec's nominal point / box decides.
  std::vector<Eigen::Vector3f> target_choices{};
  int default_choice = 0;
  OrbitView main_view{}, second_view{};  // raw-pixel cameras (second: multi_view)
};

class ReachEnv : public Env, public EnvState {
public:
  ReachEnv(ReachTaskSpec task, ReachTerms terms, const EnvConfig& config);

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult step(const Action& action) override;
  void reset_into(ObservationOut out, std::optional<std::uint64_t> seed = std::nullopt) override;
  StepOutcome step_into(const Action& action, ObservationOut out) override;
  bool step_physics_only() override;
  bool render(Image& frame) override;

  // EnvState: the task's physics state, the episode's step counter, target choice and random
  // stream; Bullet's contact caches are dropped instead (see core/env_state.hpp).
  std::string save_state() const override;
  void load_state(const std::string& bytes, const std::string& source) override;
  void drop_caches() override { task_->drop_caches(); }

  const ReachTask& task() const { return *task_; }
  ReachTask& task() { return *task_; }
  const ReachTerms& terms() const { return terms_; }
  int steps() const { return steps_; }
  // Index into terms().target_choices of the current target (-1 without choices).
  int target_index() const { return target_index_; }
  // Makes target_choices[index] the target of the current episode (for evaluation and tests).
  // rdsim::Error when there is no such choice.
  void select_target(int index);

private:
  void observe(ObservationOut out) const;
  void judge(StepOutcome& r) const;

  Spec spec_;
  ReachTerms terms_;
  std::unique_ptr<ReachTask> task_;
  std::unique_ptr<PixelView> pixels_;  // raw_pixels only
  std::unique_ptr<PixelView> viewer_;  // render_mode rgb_array only
  std::vector<Eigen::Vector3f> landmark_points_;
  std::vector<int> observed_links_;  // RobotModel link indices of terms_.observed_links
  Rng rng_;
  bool random_target_ = false;
  int target_index_ = -1;
  int steps_ = 0;
  bool done_ = true;
};

}  // namespace rdsim
