#pragma once
#include <memory>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/envs/reaching/reach_env.hpp"
#include "rdsim/render/camera.hpp"

// inmoov_tomato — RobotDrlSim section 4.3: the InMoov humanoid (assets/inmoov/inmoov.urdf, 54
// joints) moves its right palm to a tomato of a tomato tree standing in front of it. Built on
// ReachTask (envs/reach_task.hpp), which does the IK moves, bounds and distance checks.
//
// Scene (world frame = robot base frame, z up, metres): the InMoov's pedestal on the floor at the
// origin, facing +x; the tomato tree (assets/objects/tomato_tree.urdf) stands at (0.65, -0.20, 0),
// its six tomatoes (r 3.5 cm, solid) at (0.40,-0.42,1.05) (0.42,-0.22,1.02) (0.45,-0.45,1.25)
// (0.38,-0.28,1.18) (0.42,-0.15,1.30) (0.48,-0.32,1.38) (assets/README.md). No floor body: nothing
// the hand can reach is near it.
// Target: the centre of tomato_<index> (default index 3, straight ahead of the right shoulder);
// random_target: a tomato drawn uniformly from the six at each reset (seeded Rng).
// End effector: r_hand_ee, the centre of the right palm's face.
//
// Numbers (the env options' defaults, published by inmoov_tomato_defaults()):
//   physics          Bullet Featherstone, 1/240 s per physics step, gravity -9.8, 10 solver iterations
//                    (contacts only: ComputedTorque drive, no joint-limit constraint rows; the targets
//                    are clamped to the limits), action_repeat 1. The robot's links do not collide with
//                    each other; they collide with the tree.
//   home pose        every joint 0 except the right arm: upper-arm rotation -30 deg, elbow 80 deg,
//                    wrist roll -30 deg (forearm forward and a little down, palm face turned towards
//                    the tree, fingertips clear of tomato_0 below it);
//                    + U(-0.02, 0.02) rad on each IK joint at each reset (seeded).
//   held joints      head, jaw, eyes, left arm, all fingers and the torso keep their home targets; only
//                    the IK chain moves.
//   actions          Discrete(6): -x, +x, -y, +y, -z, +z palm moves of action_step (default 0.004 m:
//                    ~1 m/s at 240 Hz, what the shoulder's 1.5 rad/s allows); continuous: Box(3) of
//                    dx, dy, dz in [-1, 1] times action_step. Gaussian move noise sigma = action_step/30;
//                    goal clipped into the workspace; 3 damped-least-squares IK iterations warm-started
//                    from the current joint angles on the six right-arm joints (r_omoplate ..
//                    r_wrist_pitch; the torso joints on the path base_link -> r_hand_ee hold still).
//   workspace box    x 0.10..0.70, y -0.70..0.15, z 0.80..1.65; leaving it by more than 3 cm, or being
//                    farther than max_distance (default 0.6 m) from the tomato, ends the episode:
//                    terminated, info.out_of_bounds, reward -(max_distance x steps left).
//   observation      ground truth, 6 floats: tomato - palm (3), palm position (3); bounds in the Spec.
//   reward           -|palm - tomato| (m) every step.
//   success          |palm - tomato| < success_threshold (default 0.06 m): the tomato is solid, so the
//                    palm centre cannot come closer than its radius (0.035 m); 0.06 = palm within 2.5 cm
//                    of the skin. Terminated, info.success.
//   truncation       max_steps (default 400).
//   scripted expert  (reach_expert.hpp) to 10 cm in front of and 5 cm below the tomato, then to it:
//                    success 1.00 over 200 episodes with Discrete and with Box actions
//                    (`rdsim demos record --expert --env inmoov_tomato -n 200 --seed 3000 [--continuous]`).
//   raw_pixels       UInt8 image_height x image_width x 3 (x 6 with multi_view) from
//                    inmoov_main_view() / inmoov_second_view() below: tree, tomatoes, right arm.
//                    (image_channels: Float32 colour, depth, segmentation instead)
namespace rdsim {

EnvConfig inmoov_tomato_defaults();
ReachTaskSpec inmoov_tomato_spec(const EnvConfig& config);

// The cameras (robot at the origin facing +x, tree at (0.65, -0.2), tomatoes at z 1.0..1.4):
// main from the front-left, target (0.4, -0.25, 1.15), 1.2 m, yaw 120, pitch -20 (tree, tomatoes
// and the right arm); second from the robot's right, target (0.35, -0.3, 1.15), 1.1 m, yaw 15,
// pitch -10 (palm and tomatoes side by side). fov 60 like the paper's.
OrbitView inmoov_main_view();
OrbitView inmoov_second_view();

// What makes inmoov_tomato a task on top of ReachEnv: the targets are the tree's tomatoes
// (target_choices, read from the tree's URDF: links tomato_0, tomato_1, ...).
// rdsim::Error when the tree has fewer than default_target + 1 tomatoes.
ReachTerms inmoov_tomato_terms(const ReachTaskSpec& spec);

class InmoovTomato final : public ReachEnv {
public:
  explicit InmoovTomato(const EnvConfig& config) : InmoovTomato(inmoov_tomato_spec(config), config) {}

  // World positions of the tree's tomatoes, tomato_0 first.
  const std::vector<Eigen::Vector3f>& tomatoes() const { return terms().target_choices; }

  static constexpr int tree_index = 0;      // index of the tree in task().spec().statics
  static constexpr int default_target = 3;  // tomato_3 without random_target

private:
  InmoovTomato(const ReachTaskSpec& spec, const EnvConfig& config)
      : ReachEnv(spec, inmoov_tomato_terms(spec), config) {}
};

std::unique_ptr<Env> make_inmoov_tomato(const EnvConfig& config);

}  // namespace rdsim
