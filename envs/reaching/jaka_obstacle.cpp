#include "rdsim/envs/reaching/jaka_obstacle.hpp"

#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/jaka_button.hpp"

namespace rdsim {

EnvConfig jaka_obstacle_defaults() {
  EnvConfig c = jaka_button_defaults();
  c.name = "jaka_obstacle";
  c.max_steps = 300;     // the way round is about twice as long
  c.get<ReachOptions>().max_distance = 0.9;  // the home flange is up to 0.68 m from a random button: room for the way round
  c.options.emplace_back(ObstacleOptions{});
  return c;
}

OrbitView obstacle_main_view() {
  OrbitView v = reach_main_view();
  v.distance = 1.1f;
  v.pitch_deg = -60.0f;
  return v;
}

ReachTaskSpec jaka_obstacle_spec(const EnvConfig& config) {
  ReachTaskSpec s = jaka_button_spec(config);
  s.name = "jaka_obstacle";
  s.home << 0.66f, 1.50f, -2.32f, 2.39f, 1.5708f, 0.0f;
  Eigen::Isometry3f column = Eigen::Isometry3f::Identity();
  column.translation() << 0.35f, 0.15f, 0.0f;
  // At column_index, before the paper button's floor (if any).
  s.statics.insert(s.statics.begin() + JakaObstacle::column_index,
                   StaticBodySpec{asset_root(config.get<ReachOptions>()) + "/objects/column.urdf", column});
  // Random buttons: x 0.45..0.65, y -0.2..0.0.
  s.random_centre = Eigen::Vector3f(0.55f, -0.1f, 0.03f);
  s.target_half_range = Eigen::Vector3f(0.1f, 0.1f, 0.0f);
  return s;
}

ReachTerms jaka_obstacle_terms(const EnvConfig& config) {
  ReachTerms t;
  const ObstacleOptions& options = config.get<ObstacleOptions>();
  t.reward = options.reward;
  if (options.column_motion == ColumnMotion::RandomWalk) t.walking_body = JakaObstacle::column_index;
  t.press_body = JakaObstacle::button_index;
  t.forbidden_body = JakaObstacle::column_index;
  t.collision_reward = JakaObstacle::collision_reward;
  t.landmarks = {{JakaObstacle::column_index, "column"}};
  t.observed_links = {"wrist_2_link", "wrist_3_link"};
  // The scripted expert: round the column's near side (flange between column and base, as the header
  // says), then down onto the button from 6 cm above it (arriving sideways at button height the wrist
  // can meet the table).
  t.expert_route = {Eigen::Vector3f(0.22f, -0.05f, 0.15f)};
  t.expert_approach = Eigen::Vector3f(0.0f, 0.0f, 0.06f);
  t.main_view = obstacle_main_view();
  t.second_view = reach_second_view();
  t.cameras = {jaka_wrist_camera()};
  return t;
}

std::unique_ptr<Env> make_jaka_obstacle(const EnvConfig& config) { return std::make_unique<JakaObstacle>(config); }

}  // namespace rdsim
