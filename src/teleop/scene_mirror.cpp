#include "rdsim/teleop/scene_mirror.hpp"

#include "rdsim/core/error.hpp"
#include "rdsim/envs/reach_env.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim {

SceneMirror::SceneMirror(const EnvConfig& config) {
  EnvConfig local = config;
  local.observation = ObservationMode::GroundTruth;  // no camera of its own
  local.render_mode = RenderMode::None;
  local.urdf_root.clear();  // this machine's assets, wherever the env itself runs
  std::unique_ptr<Env> env = make_env(local);
  auto* reach = dynamic_cast<ReachEnv*>(env.get());
  if (!reach) throw Error("env " + config.name + " has no robot scene to show (the reaching envs have one)");
  env.release();
  env_.reset(reach);
  add_task_bodies(scene_, env_->task());
}

SceneMirror::~SceneMirror() = default;

void SceneMirror::update(const RobotSnapshot& state) {
  ReachTask& task = env_->task();
  if (state.joint_positions.size() == task.robot().dof()) task.robot().reset_joints(state.joint_positions);
  task.set_target(state.target);
  update_poses(scene_, task.world());
}

OrbitView SceneMirror::main_view() const { return env_->terms().main_view; }

}  // namespace rdsim
