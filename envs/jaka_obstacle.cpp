#include "rdsim/envs/jaka_obstacle.hpp"

#include "rdsim/envs/jaka_button.hpp"
#include "rdsim/error.hpp"

namespace rdsim {

ReachTaskSpec jaka_obstacle_spec(const EnvConfig& config) {
  ReachTaskSpec s = jaka_button_spec(config);
  s.home << 0.66f, 1.50f, -2.32f, 2.39f, 1.5708f, 0.0f;
  Eigen::Isometry3f column = Eigen::Isometry3f::Identity();
  column.translation() << 0.35f, 0.15f, 0.0f;
  s.statics.push_back({asset_root(config) + "/objects/column.urdf", column});
  // Random buttons: x 0.45..0.65, y -0.2..0.0.
  s.random_centre = Eigen::Vector3f(0.55f, -0.1f, 0.03f);
  s.target_half_range = Eigen::Vector3f(0.1f, 0.1f, 0.0f);
  if (config.max_steps == 0) s.max_steps = 300;  // the way round is about twice as long
  // The home flange is up to 0.68 m from a random button: leave room for the way round.
  if (config.max_distance == 0.0) s.max_distance = 0.9f;
  return s;
}

JakaObstacle::JakaObstacle(const EnvConfig& config) {
  task_ = std::make_unique<ReachTask>(jaka_obstacle_spec(config));
  discrete_ = config.is_discrete;
  random_target_ = config.random_target;
  const ReachTaskSpec& s = task_->spec();
  column_ = s.statics[column_index].pose.translation();
  spec_.env_name = "jaka_obstacle";
  spec_.action = reach_action_space(discrete_);
  spec_.max_episode_steps = s.max_steps;
  spec_.control_dt = s.world.time_step * s.action_repeat;
  const Eigen::Vector3f lo = s.workspace.min() - Eigen::Vector3f::Constant(s.workspace_margin);
  const Eigen::Vector3f hi = s.workspace.max() + Eigen::Vector3f::Constant(s.workspace_margin);
  const Eigen::Vector3f reach = (hi - lo).cwiseMax(Eigen::Vector3f::Constant(s.max_distance));
  spec_.observation.type = ObsType::Float32;
  spec_.observation.shape = {9};
  spec_.observation.low.resize(9);
  spec_.observation.high.resize(9);
  for (int i = 0; i < 3; ++i) {  // element-wise: GCC 12 warns (-Warray-bounds) on Vector3f comma-init here
    spec_.observation.low[i] = -reach[i];
    spec_.observation.high[i] = reach[i];
    spec_.observation.low[3 + i] = lo[i] - column_[i];
    spec_.observation.high[3 + i] = hi[i] - column_[i];
    spec_.observation.low[6 + i] = lo[i];
    spec_.observation.high[6 + i] = hi[i];
  }
  if (config.observation == ObservationMode::RawPixels) {
    pixels_ = std::make_unique<PixelView>(*task_, config, obstacle_main_view(), reach_second_view());
    spec_.observation = pixels_->space();
  }
}

Observation JakaObstacle::observe() const {
  Observation o;
  if (pixels_) {
    pixels_->render(*task_, o.pixels);
    return o;
  }
  o.values.resize(9);
  const Eigen::Vector3f& ee = task_->ee_position();
  const Eigen::Vector3f rel = task_->target() - ee;
  for (int i = 0; i < 3; ++i) {
    o.values[i] = rel[i];
    o.values[3 + i] = ee[i] - column_[i];
    o.values[6 + i] = ee[i];
  }
  return o;
}

Observation JakaObstacle::reset(std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  task_->reset(rng_, random_target_);
  steps_ = 0;
  done_ = false;
  return observe();
}

StepResult JakaObstacle::step(const Action& action) {
  const Eigen::Vector3f move = move_for_action(action, discrete_, task_->spec().step, spec_.env_name);
  StepResult r;
  if (done_) {
    r.observation = observe();
    r.terminated = true;
    return r;
  }
  task_->apply_move(move, rng_);
  task_->step_physics();
  ++steps_;
  const ReachTaskSpec& s = task_->spec();
  const float d = task_->distance();
  r.observation = observe();
  r.reward = -d;
  r.info.distance = d;
  r.info.collision = task_->robot_touches(column_index);
  r.info.success = !r.info.collision &&
                   (task_->reached() || task_->world().touching({task_->robot().body(), task_->ee_link()},
                                                                {task_->static_body(button_index), -1}));
  r.info.out_of_bounds = !r.info.success && !r.info.collision && task_->out_of_bounds();
  if (r.info.collision) r.reward = collision_reward;
  if (r.info.out_of_bounds) r.reward -= s.max_distance * static_cast<float>(s.max_steps - steps_);
  r.terminated = r.info.success || r.info.collision || r.info.out_of_bounds;
  r.truncated = !r.terminated && steps_ >= s.max_steps;
  done_ = r.terminated || r.truncated;
  return r;
}

bool JakaObstacle::step_physics_only() {
  task_->step_physics();
  return true;
}

std::unique_ptr<Env> make_jaka_obstacle(const EnvConfig& config) { return std::make_unique<JakaObstacle>(config); }

}  // namespace rdsim
