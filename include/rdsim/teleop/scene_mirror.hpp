#pragma once
#include <memory>

#include "rdsim/core/env_config.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/camera.hpp"

// What the teleoperation window draws of an env it may not own (an `rdsim serve` session): a local
// copy of the env's robot and static bodies, built from the same env config with this machine's
// assets and posed from RobotControl::robot_state (joint positions, the target). The copy never
// steps; it only holds poses. The same code serves in-process and remote envs.
namespace rdsim {

class ReachEnv;

class SceneMirror {
public:
  // rdsim::Error when `config` names an env without a robot scene (not a reaching env).
  explicit SceneMirror(const EnvConfig& config);
  ~SceneMirror();

  // Poses every part from the robot's joint positions and the task's target, and marks the
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

  std::unique_ptr<ReachEnv> env_;
  RobotScene scene_;
  int target_item_ = -1;
  Eigen::Vector4f target_item_rgba_ = Eigen::Vector4f::Zero();  // its own colour, restored when the target moves
};

}  // namespace rdsim
