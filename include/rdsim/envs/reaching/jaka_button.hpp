#pragma once
#include <memory>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/reaching/button_options.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/render/camera.hpp"

// jaka_button — RobotDrlSim section 4.1: a JAKA Zu 7 arm moves its flange to a push button on a table.
//
// Scene (world frame = robot base frame, z up, metres): the table top (assets/objects/table.urdf,
// 1.2 x 1.2 m) is the plane z = 0, its centre at (0.35, 0); the robot base stands on it at the
// origin; the button (assets/objects/button.urdf, r 4 cm, 3 cm high) stands on it at (0.5, 0, 0)
// as in the paper. The target point is the centre of the button's top, (0.5, 0, 0.03).
// button paper: the original's free 5 kg button (assets/objects/paper_button.urdf, 20 x 20 x 3.7 cm)
// stands there instead, and the target is the centre of its bottom face, (0.5, 0, 0), moving with it;
// a collision-only floor at the table top's height (assets/objects/paper_floor.urdf, the original's
// floor plane) carries it on when it is pushed off the table.
// random_target: the button moves by x += 0.15 U(-1,1), y += 0.3 U(-1,1) (the paper's box: x 0.35..0.65,
// y -0.3..0.3), drawn from the env's Rng at each reset; every such point is reachable tool-down.
// End effector: flange_link (centre of the flange face).
//
// Numbers (the env options' defaults, published by jaka_button_defaults()):
//   physics          Bullet Featherstone, 1/240 s per physics step, gravity -9.8, 10 solver
//                    iterations (contacts only: ComputedTorque drive, no limit constraint rows;
//                    set_position_targets clamps to the joint limits), action_repeat 1.
//   home pose        joints (-0.26, 1.44, -1.85, 1.98, 1.5708, 0) rad: flange at about (0.45, 0, 0.25),
//                    pointing down; + U(-0.02, 0.02) rad per joint at each reset (seeded).
//   actions          Discrete(6) (is_discrete): -x, +x, -y, +y, -z, +z flange moves of action_step
//                    (default 0.015 m); continuous: Box(3) of dx, dy, dz in [-1, 1] times action_step.
//                    Each move gets Gaussian noise sigma = action_step / 30 per axis (rdsim adds it),
//                    the goal is clipped into the workspace box and turned into joint targets by one
//                    damped-least-squares IK step (damping 0.02 m) from the current joint angles; when
//                    a joint would exceed its speed limit (180 deg/s) within the step, the whole joint
//                    step is scaled down, so the flange slows down rather than leaving the line.
//                    The arm's dynamics limit what a move achieves: a steady direction gives about
//                    6-7 mm per step, random actions about 2 mm along the chosen axis.
//   workspace box    x 0.15..0.85, y -0.5..0.5, z 0.02..0.55 (robot frame); leaving it by more than
//                    3 cm, or being farther than max_distance (default 0.7 m) from the target, ends
//                    the episode: terminated, info.out_of_bounds, reward -(max_distance x steps left).
//   observation      ground truth, 6 floats: target - flange (3), flange position (3); bounds in the Spec.
//                    raw_pixels: UInt8 image_height x image_width x 3 (x 6 with multi_view) from the
//                    paper's cameras re-aimed at this layout (reach_main_view / reach_second_view below).
//                    (image_channels: Float32 colour, depth, segmentation instead)
//   reward           -|flange - target| (m) every step.
//   success          |flange - target| < success_threshold (default 0.025 m) or the flange touching
//                    the button: terminated, info.success.
//   truncation       max_steps (default 200; the paper used 1000).
namespace rdsim {

// The env options above with jaka_button's values (registry: default_env_config("jaka_button")).
EnvConfig jaka_button_defaults();

// The paper's two cameras (same yaw, pitch, fov) re-aimed at this layout, where the robot base is
// the world origin on the table top (z = 0) and targets lie around x 0.35..0.65: the paper's
// targets/distances (main: (0.316, -0.2, -0.1), 1.6 m) put the robot in a corner of the image and
// made the button 2-3 pixels wide at 64x64. Main: target (0.32, 0.05, 0.15), 1.0 m, yaw 155, pitch -36.
// Second (multi_view): target (0.45, 0.1, 0.1), 1.1 m, yaw 32, pitch -13. jaka_obstacle uses them too.
OrbitView reach_main_view();
OrbitView reach_second_view();

// The jaka_button scene and numbers above, with `config`'s task numbers.
ReachTaskSpec jaka_button_spec(const EnvConfig& config);

// What makes jaka_button a task on top of ReachEnv: the button is pressed, nothing is forbidden.
ReachTerms jaka_button_terms();

class JakaButton final : public ReachEnv {
public:
  explicit JakaButton(const EnvConfig& config) : ReachEnv(jaka_button_spec(config), jaka_button_terms(), config) {}
  static constexpr int button_index = 1;  // index of the button in task().spec().statics
};

std::unique_ptr<Env> make_jaka_button(const EnvConfig& config);

}  // namespace rdsim
