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

  // Poses every part from the robot's joint positions and the task's target.
  void update(const RobotSnapshot& state);

  const Scene& scene() const { return scene_.scene; }
  // The env's own main camera (its raw-pixel view): where the window's camera starts.
  OrbitView main_view() const;

private:
  std::unique_ptr<ReachEnv> env_;
  RobotScene scene_;
};

}  // namespace rdsim
