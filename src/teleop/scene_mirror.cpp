#include "rdsim/teleop/scene_mirror.hpp"

#include "rdsim/core/error.hpp"
#include "rdsim/envs/manipulation/manipulation_env.hpp"
#include "rdsim/envs/reaching/reach_arm.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim {

SceneMirror::SceneMirror(const EnvConfig& config) {
  EnvConfig local = config;
  local.observation = ObservationMode::GroundTruth;  // no camera of its own
  local.render_mode = RenderMode::None;
  if (auto* reach = local.find<ReachOptions>()) reach->urdf_root.clear();  // this machine's assets, wherever the env itself runs
  env_ = make_env(local);
  if (auto* reach = dynamic_cast<ReachEnv*>(env_.get())) {
    task_ = &reach->task();
    view_ = reach->terms().main_view;
    target_choices_ = reach->terms().target_choices.size();
  } else if (auto* manipulation = dynamic_cast<ManipulationEnv*>(env_.get())) {
    task_ = &manipulation->world();
    view_ = arm_main_view(task_->spec().workspace);
  } else {
    throw Error("env " + config.name + " has no robot scene to show (the reaching and manipulation envs have one)");
  }
  add_task_bodies(scene_, *task_);
}

SceneMirror::~SceneMirror() = default;

void SceneMirror::update(const RobotSnapshot& state) {
  ReachTask& task = *task_;
  if (state.joint_positions.size() == task.robot().dof()) task.robot().reset_joints(state.joint_positions);
  task.set_target(state.target);
  // The other bodies where the env has them (a pushed cube, a goal marker), when it says.
  if (state.bodies.size() == task.spec().statics.size())
    for (size_t i = 0; i < state.bodies.size(); ++i) {
      Eigen::Isometry3f pose(state.bodies[i].orientation.normalized());
      pose.translation() = state.bodies[i].position;
      task.world().set_static_pose(task.static_body(static_cast<int>(i)), pose);
    }
  update_poses(scene_, task.world());
  mark_target(state.target);
}

void SceneMirror::mark_target(const Eigen::Vector3f& target) {
  // An item "is" the target when its centre lies within 1 cm of the target point (the tomatoes
  // are spheres centred on their links, which the targets are: envs/reaching/inmoov_tomato.cpp).
  constexpr float kCentreTolerance = 0.01f;  // m
  // Only a target among several alike (the env's target_choices) needs a mark; a lone button does not.
  if (target_choices_ < 2) return;
  int found = -1;
  float best = kCentreTolerance;
  for (const ScenePart& part : scene_.parts) {
    if (part.link != -1) continue;  // robot items: never the target
    const float d = (scene_.scene.items[static_cast<size_t>(part.item)].pose.translation() - target).norm();
    if (d < best) {
      best = d;
      found = part.item;
    }
  }
  if (found == target_item_) return;
  if (target_item_ >= 0) scene_.scene.items[static_cast<size_t>(target_item_)].rgba = target_item_rgba_;
  target_item_ = found;
  if (found >= 0) {
    target_item_rgba_ = scene_.scene.items[static_cast<size_t>(found)].rgba;
    scene_.scene.items[static_cast<size_t>(found)].rgba = target_colour();
  }
}

OrbitView SceneMirror::main_view() const { return view_; }

}  // namespace rdsim
