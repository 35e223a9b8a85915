#pragma once
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/render/camera.hpp"

// jaka_obstacle — RobotDrlSim section 4.2: jaka_button's scene and numbers (see jaka_button.hpp) with
// an obstacle column the arm must go around.
//
// Column: assets/objects/column.urdf (cylinder r 0.05 m, 0.60 m high) standing on the table at
// (0.35, 0.15, 0), i.e. beside the base-to-button line, not on it: the 0.6 m column is taller than the
// Zu 7's links at that distance, so a column ON that line would leave no collision-free way to the
// button at all. Instead the flange starts on the column's far side from the button:
//   home pose        joints (0.66, 1.50, -2.32, 2.39, 1.5708, 0) rad: flange at about (0.20, 0.30, 0.15),
//                    pointing down (+ U(-0.02, 0.02) rad per joint at reset, seeded);
// so the straight line (and the greedy axis-by-axis staircase) from there to every button position runs
// through the column, while the way round its near side (flange passing about (0.25, -0.05), between
// the column and the robot base) is free. Going round the far side is not: the arm would sweep over
// the column.
//   button           nominal (0.5, 0, 0) as in jaka_button; random_target: x 0.45..0.65, y -0.2..0.0
//                    (the part of the paper's box that the column leaves clear by >= 0.1 m and that the
//                    near-side detour reaches).
//   observation      15 floats: button - flange (3), flange - column (3; the column's base centre),
//                    flange position (3), then two documented extras: wrist_2_link - column (3) and
//                    wrist_3_link - column (3), the links' frame origins. Why: any link touching the
//                    column ends the episode, and it is the wrist that touches it (it sits about
//                    0.11 m to the side of the flange, towards the column on the near-side way round),
//                    so the flange's own clearance does not say whether the arm passes. With the shipped config
//                    (seed 3), collisions over the last 1,500 training episodes: 1.7 % without the
//                    extras, 0.7 % with them.
//                    raw_pixels: UInt8 image_height x image_width x 3 (x 6 with multi_view), cameras
//                    obstacle_main_view below (steeper than jaka_button's, so the column does not
//                    hide the flange) and jaka_button's reach_second_view.
//                    (image_channels: Float32 colour, depth, segmentation instead)
//   reward           -|flange - button| per step; touching the column with ANY robot link: reward -200,
//                    terminated, info.collision.
//   truncation       max_steps, default 300 (the way round is about twice as long as jaka_button's).
//   max_distance     default 0.9 m (the home flange is up to 0.68 m from a random button).
//   scripted expert  (reach_expert.hpp) via (0.22, -0.05, 0.15), the near side, then to 6 cm above the
//                    button, then down: success 1.00 over 200 episodes with Discrete and with Box actions
//                    (`rdsim demos record --expert --env jaka_obstacle -n 200 [--continuous]`).
//   success, workspace, out-of-bounds, physics, actions: as jaka_button.
namespace rdsim {

EnvConfig jaka_obstacle_defaults();  // jaka_button's, with max_steps 300 and max_distance 0.9 m

// jaka_button's reach_main_view() looking down steeper (pitch -60, 1.1 m), because from -36 deg
// the column hides the flange at its home pose beside it; button, column and flange all visible.
OrbitView obstacle_main_view();

ReachTaskSpec jaka_obstacle_spec(const EnvConfig& config);

// What makes jaka_obstacle a task on top of ReachEnv: the button is pressed, the column is
// forbidden and observed; config's reward rule, and the column random-walks with column_motion
// random_walk.
ReachTerms jaka_obstacle_terms(const EnvConfig& config);

class JakaObstacle final : public ReachEnv {
public:
  explicit JakaObstacle(const EnvConfig& config)
      : ReachEnv(jaka_obstacle_spec(config), jaka_obstacle_terms(config), config) {}

  static constexpr int button_index = 1;  // in task().spec().statics
  static constexpr int column_index = 2;
  static constexpr float collision_reward = -200.0f;
};

std::unique_ptr<Env> make_jaka_obstacle(const EnvConfig& config);

}  // namespace rdsim
