#pragma once
#include <cstddef>
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/camera.hpp"

// What the teleoperation window draws of an env it may not own (an `rdsim serve` session): a local
// copy of the env's robot and static bodies, built from the same env config with this machine's
// assets and posed from RobotControl::robot_state (joint positions, the target). The copy never
// steps; it only holds poses. The same code serves in-process and remote envs.
namespace rdsim {

class ReachTask;

class SceneMirror {
public:
  // rdsim::Error when `config` names an env without a robot scene (not a reaching or manipulation env).
  explicit SceneMirror(const EnvConfig& config);
  ~SceneMirror();

  // Poses every part from the robot's joint positions, the task's target and its other bodies' poses
  // (RobotSnapshot::bodies: cubes, goal markers), and marks the
  // target: the static body's item centred on it (inmoov_tomato's target tomato among the ~8 on
  // the tree) takes target_colour(), the others their URDF colours.
  void update(const RobotSnapshot& state);

  // The marked item (index into scene().items), or -1 when the env has no choice of targets
  // (jaka_button's button is the only one: no mark) or no static item is centred on the target.
  int target_item() const { return target_item_; }
  // The target's mark: a ripe yellow, far from the tree's reds and greens.
  static Eigen::Vector4f target_colour() { return {1.0f, 0.85f, 0.0f, 1.0f}; }

  const Scene& scene() const { return scene_.scene; }
  // The env's own main camera (its raw-pixel view): where the window's camera starts.
  OrbitView main_view() const;

private:
  void mark_target(const Eigen::Vector3f& target);

  std::unique_ptr<Env> env_;  // a reaching or manipulation env, never stepped
  ReachTask* task_ = nullptr;  // its world
  OrbitView view_{};
  std::size_t target_choices_ = 0;  // the reaching env's choice of targets (inmoov_tomato's tomatoes)
  RobotScene scene_;
  int target_item_ = -1;
  Eigen::Vector4f target_item_rgba_ = Eigen::Vector4f::Zero();  // its own colour, restored when the target moves
};

}  // namespace rdsim
