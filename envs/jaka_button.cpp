#include "rdsim/envs/jaka_button.hpp"

#include "rdsim/error.hpp"

namespace rdsim {
namespace {

Eigen::Isometry3f at(float x, float y, float z) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translation() << x, y, z;
  return t;
}

}  // namespace

ReachTaskSpec jaka_button_spec(const EnvConfig& config) {
  const std::string assets = asset_root(config);
  ReachTaskSpec s;
  s.robot_urdf = assets + "/jaka/jaka_zu7.urdf";
  s.ee_link = "flange_link";
  s.home.resize(6);
  s.home << -0.26f, 1.44f, -1.85f, 1.98f, 1.5708f, 0.0f;
  s.home_noise = 0.02f;
  s.statics = {{assets + "/objects/table.urdf", at(0.35f, 0.0f, 0.0f)},
               {assets + "/objects/button.urdf", at(0.5f, 0.0f, 0.0f)}};
  s.target_body = JakaButton::button_index;
  s.target_offset = Eigen::Vector3f(0.0f, 0.0f, 0.03f);  // the top of the button
  s.nominal_target = Eigen::Vector3f(0.5f, 0.0f, 0.03f);
  s.target_half_range = Eigen::Vector3f(0.15f, 0.3f, 0.0f);
  s.workspace = Eigen::AlignedBox3f(Eigen::Vector3f(0.15f, -0.5f, 0.02f), Eigen::Vector3f(0.85f, 0.5f, 0.55f));
  s.step = 0.015f;
  s.move_noise = 1.0f / 30.0f;
  s.success_threshold = 0.025f;
  s.max_distance = 0.7f;
  s.workspace_margin = 0.03f;
  s.max_steps = 200;
  s.action_repeat = 1;
  s.ik_iterations = 1;
  s.world.time_step = 1.0 / 240.0;
  s.world.solver_iterations = 10;
  s.robot.drive = JointDrive::ComputedTorque;
  s.robot.limit_constraints = false;
  apply_env_config(config, s);
  return s;
}

JakaButton::JakaButton(const EnvConfig& config) {
  task_ = std::make_unique<ReachTask>(jaka_button_spec(config));
  discrete_ = config.is_discrete;
  random_target_ = config.random_target;
  const ReachTaskSpec& s = task_->spec();
  spec_.env_name = "jaka_button";
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
  for (int i = 0; i < 3; ++i) {  // element-wise: GCC 12 warns (-Warray-bounds) on Vector3f comma-init here
    spec_.observation.low[i] = -reach[i];
    spec_.observation.high[i] = reach[i];
    spec_.observation.low[3 + i] = lo[i];
    spec_.observation.high[3 + i] = hi[i];
  }
  if (config.observation == ObservationMode::RawPixels) {
    pixels_ = std::make_unique<PixelView>(*task_, config, reach_main_view(), reach_second_view());
    spec_.observation = pixels_->space();
  }
}

Observation JakaButton::observe() const {
  Observation o;
  if (pixels_) {
    pixels_->render(*task_, o.pixels);
    return o;
  }
  o.values.resize(6);
  const Eigen::Vector3f& ee = task_->ee_position();
  const Eigen::Vector3f rel = task_->target() - ee;
  for (int i = 0; i < 3; ++i) {
    o.values[i] = rel[i];
    o.values[3 + i] = ee[i];
  }
  return o;
}

Observation JakaButton::reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  task_->reset(rng_, random_target_);
  steps_ = 0;
  done_ = false;
  return observe();
}

StepResult JakaButton::step(const Action& action) {
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
  r.observation = observe();
  r.reward = -d;
  r.info.distance = d;
  const ReachTaskSpec& s = task_->spec();
  r.info.success = task_->reached() ||
                   task_->world().touching({task_->robot().body(), task_->ee_link()},
                                           {task_->static_body(button_index), -1});
  r.info.out_of_bounds = !r.info.success && task_->out_of_bounds();
  if (r.info.out_of_bounds) r.reward -= s.max_distance * static_cast<float>(s.max_steps - steps_);
  r.terminated = r.info.success || r.info.out_of_bounds;
  r.truncated = !r.terminated && steps_ >= s.max_steps;
  done_ = r.terminated || r.truncated;
  return r;
}

bool JakaButton::step_physics_only() {
  task_->step_physics();
  return true;
}

std::unique_ptr<Env> make_jaka_button(const EnvConfig& config) { return std::make_unique<JakaButton>(config); }

}  // namespace rdsim
