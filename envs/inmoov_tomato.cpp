#include "rdsim/envs/inmoov_tomato.hpp"

#include <cmath>
#include <string>

#include "rdsim/error.hpp"
#include "rdsim/urdf_loader.hpp"

namespace rdsim {
namespace {

constexpr float kDeg = static_cast<float>(M_PI / 180.0);

Eigen::Isometry3f at(float x, float y, float z) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translation() << x, y, z;
  return t;
}

// Every joint 0 except the right arm's rotation and elbow (see the header); one value per robot dof.
Eigen::VectorXf home_pose(const RobotModel& model) {
  Eigen::VectorXf q = Eigen::VectorXf::Zero(model.movable_joint_count());
  int dof = 0;
  for (const Joint& j : model.joints) {
    if (!j.movable()) continue;
    if (j.name == "r_upper_arm_rotate") q[dof] = -30.0f * kDeg;
    if (j.name == "r_elbow") q[dof] = 90.0f * kDeg;
    ++dof;
  }
  return q;
}

}  // namespace

ReachTaskSpec inmoov_tomato_spec(const EnvConfig& config) {
  const std::string assets = asset_root(config);
  ReachTaskSpec s;
  s.robot_urdf = assets + "/inmoov/inmoov.urdf";
  s.ee_link = "r_hand_ee";
  s.home = home_pose(load_urdf(s.robot_urdf));
  s.home_noise = 0.02f;
  s.statics = {{assets + "/objects/tomato_tree.urdf", at(0.65f, -0.20f, 0.0f)}};
  s.target_body = -1;  // the tomatoes are part of the tree: the target is set per reset
  s.workspace = Eigen::AlignedBox3f(Eigen::Vector3f(0.10f, -0.70f, 0.80f), Eigen::Vector3f(0.70f, 0.15f, 1.65f));
  s.step = 0.004f;
  s.move_noise = 1.0f / 30.0f;
  s.success_threshold = 0.06f;
  s.max_distance = 0.6f;
  s.workspace_margin = 0.03f;
  s.max_steps = 400;
  s.action_repeat = 1;
  s.ik_iterations = 3;
  s.world.time_step = 1.0 / 240.0;
  s.world.solver_iterations = 10;
  s.robot.drive = JointDrive::ComputedTorque;
  s.robot.limit_constraints = false;
  apply_env_config(config, s);
  return s;
}

InmoovTomato::InmoovTomato(const EnvConfig& config) {
  task_ = std::make_unique<ReachTask>(inmoov_tomato_spec(config));
  discrete_ = config.is_discrete;
  random_target_ = config.random_target;
  const ReachTaskSpec& s = task_->spec();
  const RobotModel& tree = task_->static_model(tree_index);
  const auto poses = tree.link_poses_at_zero();
  for (int i = 0;; ++i) {
    const int link = tree.link_index("tomato_" + std::to_string(i));
    if (link < 0) break;
    tomatoes_.push_back(s.statics[tree_index].pose * poses[static_cast<size_t>(link)].translation().cast<float>());
  }
  if (static_cast<int>(tomatoes_.size()) <= default_target)
    throw Error(s.statics[tree_index].urdf + ": inmoov_tomato needs links tomato_0 .. tomato_" +
                std::to_string(default_target) + ", found " + std::to_string(tomatoes_.size()));
  task_->set_target(tomatoes_[default_target]);

  spec_.env_name = "inmoov_tomato";
  spec_.action = reach_action_space(discrete_);
  spec_.max_episode_steps = s.max_steps;
  spec_.control_dt = s.world.time_step * s.action_repeat;
  const Eigen::Vector3f lo = s.workspace.min() - Eigen::Vector3f::Constant(s.workspace_margin);
  const Eigen::Vector3f hi = s.workspace.max() + Eigen::Vector3f::Constant(s.workspace_margin);
  const Eigen::Vector3f reach = (hi - lo).cwiseMax(Eigen::Vector3f::Constant(s.max_distance));
  spec_.observation.type = ObsType::Float32;
  spec_.observation.shape = {6};
  spec_.observation.low.resize(6);
  spec_.observation.high.resize(6);
  // Segment writes, not a comma initialiser: GCC 12 warns (-Warray-bounds) on the latter here.
  spec_.observation.low.head<3>() = -reach;
  spec_.observation.low.tail<3>() = lo;
  spec_.observation.high.head<3>() = reach;
  spec_.observation.high.tail<3>() = hi;
  if (config.observation == ObservationMode::RawPixels) {
    pixels_ = std::make_unique<PixelView>(*task_, config, inmoov_main_view(), inmoov_second_view());
    spec_.observation = pixels_->space();
  }
}

Observation InmoovTomato::observe() const {
  Observation o;
  if (pixels_) {
    pixels_->render(*task_, o.pixels);
    return o;
  }
  o.values.resize(6);
  o.values << task_->target() - task_->ee_position(), task_->ee_position();
  return o;
}

Observation InmoovTomato::reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  task_->reset(rng_, false);
  target_index_ = random_target_ ? static_cast<int>(rng_.below(tomatoes_.size())) : default_target;
  task_->set_target(tomatoes_[static_cast<size_t>(target_index_)]);
  steps_ = 0;
  done_ = false;
  return observe();
}

void InmoovTomato::select_target(int index) {
  if (index < 0 || index >= static_cast<int>(tomatoes_.size()))
    throw Error("inmoov_tomato: no tomato " + std::to_string(index) + " (the tree has " +
                std::to_string(tomatoes_.size()) + ")");
  target_index_ = index;
  task_->set_target(tomatoes_[static_cast<size_t>(index)]);
}

StepResult InmoovTomato::step(const Action& action) {
  const Eigen::Vector3f move = move_for_action(action, discrete_, task_->spec().step, spec_.env_name);
  StepResult r;
  if (done_) {
    // Stepping a finished episode: nothing moves, no reward.
    r.observation = observe();
    r.terminated = true;
    return r;
  }
  task_->apply_move(move, rng_);
  task_->step_physics();
  ++steps_;
  const float d = task_->distance();
  const ReachTaskSpec& s = task_->spec();
  r.observation = observe();
  r.reward = -d;
  r.info.distance = d;
  r.info.success = task_->reached();
  r.info.out_of_bounds = !r.info.success && task_->out_of_bounds();
  if (r.info.out_of_bounds) r.reward -= s.max_distance * static_cast<float>(s.max_steps - steps_);
  r.terminated = r.info.success || r.info.out_of_bounds;
  r.truncated = !r.terminated && steps_ >= s.max_steps;
  done_ = r.terminated || r.truncated;
  return r;
}

bool InmoovTomato::step_physics_only() {
  task_->step_physics();
  return true;
}

std::unique_ptr<Env> make_inmoov_tomato(const EnvConfig& config) { return std::make_unique<InmoovTomato>(config); }

}  // namespace rdsim
