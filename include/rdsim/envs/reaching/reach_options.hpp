#pragma once
#include <string>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/env_config.hpp"

// The options of every reaching task (jaka_button, jaka_obstacle, inmoov_tomato, reach): how a move's
// end-effector goal becomes joint targets, which joints may move, how the joints are driven, where
// an episode starts and ends, and what the ground-truth vector holds. One option group
// (core/env_options.hpp) in each reaching env's defaults; the describe() below is the one
// declaration of these keys. envs/reach_task.hpp and envs/reach_env.hpp implement them.
namespace rdsim {

enum class IkMethod { DampedLeastSquares, NullSpace };
enum class IkJoints { Arm, All };
enum class DriveMode { ComputedTorque, PositionMotor };
enum class ResetPose { Home, Rest };
enum class ObservationLayout { Full, Relative };

// The initial values are the generic ones; each task publishes its own (e.g. jaka_button_defaults).
struct ReachOptions {
  bool random_target = false;
  double max_distance = 0.7;        // m
  std::string urdf_root{};          // empty = the repo's assets/ (asset_root)
  double action_step = 0.015;       // m
  double success_threshold = 0.025; // m
  int action_repeat = 1;
  int solver_iterations = 10;
  IkMethod ik_method = IkMethod::DampedLeastSquares;
  int ik_iterations = 1;
  IkJoints ik_joints = IkJoints::Arm;
  DriveMode drive = DriveMode::ComputedTorque;
  double position_gain = 1.0;       // kp
  double velocity_gain = 1.0;       // kd
  double move_noise = 1.0 / 30.0;   // sigma as a fraction of action_step
  bool workspace_bounds = true;
  bool end_on_success = true;
  ResetPose reset_pose = ResetPose::Home;
  double reset_noise = 0.02;        // rad
  ObservationLayout observation_layout = ObservationLayout::Full;
};

inline const config::Names<IkMethod>& ik_method_names() {
  static const config::Names<IkMethod> names = {{"damped_least_squares", IkMethod::DampedLeastSquares},
                                                {"null_space", IkMethod::NullSpace}};
  return names;
}
inline const config::Names<IkJoints>& ik_joints_names() {
  static const config::Names<IkJoints> names = {{"arm", IkJoints::Arm}, {"all", IkJoints::All}};
  return names;
}
inline const config::Names<DriveMode>& drive_mode_names() {
  static const config::Names<DriveMode> names = {{"computed_torque", DriveMode::ComputedTorque},
                                                 {"position_motor", DriveMode::PositionMotor}};
  return names;
}
inline const config::Names<ResetPose>& reset_pose_names() {
  static const config::Names<ResetPose> names = {{"home", ResetPose::Home}, {"rest", ResetPose::Rest}};
  return names;
}
inline const config::Names<ObservationLayout>& observation_layout_names() {
  static const config::Names<ObservationLayout> names = {{"full", ObservationLayout::Full},
                                                         {"relative", ObservationLayout::Relative}};
  return names;
}

template <class V, class C>
  requires config::Describes<C, ReachOptions>
void describe(V& v, C& c) {
  v.field("random_target", c.random_target, "target drawn at each reset");
  v.field("max_distance", c.max_distance, config::Range{1e-3, 100.0},
          "m; farther than this from the target ends the episode");
  v.field("urdf_root", c.urdf_root, "folder holding the URDF assets; empty = the repo's assets/");
  v.field("action_step", c.action_step, config::Range{1e-4, 2.0},
          "m per discrete move / largest continuous move (the end-effector goal of one move; the robot's "
          "dynamics decide how far it gets within one env step)");
  v.field("success_threshold", c.success_threshold, config::Range{1e-4, 10.0}, "m; closer than this to the target is success");
  v.field("action_repeat", c.action_repeat, config::Range{1, 1000},
          "physics steps (1/240 s each) per env step; the move's joint targets hold for all of them");
  v.field("solver_iterations", c.solver_iterations, config::Range{1, 10'000},
          "Bullet sequential-impulse solver iterations per physics step (contacts, motors, joint limits)");
  v.choice("ik_method", c.ik_method, ik_method_names(),
           "how a move's goal becomes joint targets, by ik_iterations steps from the current joint angles: "
           "damped_least_squares (damping 0.02 m) or null_space (pybullet's calculateInverseKinematics with "
           "rest poses: damping 0.6, a pull of 0.001 x (rest pose - q) in the Jacobian's null space, at most "
           "45 deg per joint per step, stops within 0.1 mm)");
  v.field("ik_iterations", c.ik_iterations, config::Range{1, 1000}, "IK steps per move (one FK + Jacobian each)");
  v.choice("ik_joints", c.ik_joints, ik_joints_names(),
           "joints the IK moves: arm (the task's arm joints) or all (every joint on the path from the base to "
           "the end effector; the InMoov's torso too). Joints off that path hold their targets either way");
  v.choice("drive", c.drive, drive_mode_names(),
           "joint drive: computed_torque (torques from the arm's dynamics within the URDF efforts; the IK "
           "step is slowed so no joint passes its URDF speed limit) or position_motor (pybullet's "
           "POSITION_CONTROL: Bullet joint motors with force = URDF effort and joint-limit constraints, "
           "solved with the contacts; the IK solution is the motors' target as it is)");
  v.field("position_gain", c.position_gain, config::Range{1e-4, 1.0},
          "kp of the drive law: joint speed = kp (target - q) / dt + (1 - kd) qdot, within the URDF speed limit");
  v.field("velocity_gain", c.velocity_gain, config::Range{0.0, 1.0}, "kd of that law (target velocity 0)");
  v.field("move_noise", c.move_noise, config::Range{0.0, 1.0},
          "Gaussian noise on each component of a move's goal, sigma = move_noise x action_step");
  v.field("workspace_bounds", c.workspace_bounds,
          "move goals are clipped into the task's workspace box, and leaving it (by 3 cm) or being farther "
          "than max_distance from the target ends the episode; false: neither");
  v.field("end_on_success", c.end_on_success,
          "success ends the episode; false: episodes end at max_steps (or a failure) and info.success is "
          "whether the success rule holds at the episode's last step");
  v.choice("reset_pose", c.reset_pose, reset_pose_names(),
           "joint angles at reset: home (the task's working pose) or rest (RobotDrlSim's: Jaka "
           "[0,0,1,1,1,1], InMoov all 0; also null_space's rest pose)");
  v.field("reset_noise", c.reset_noise, config::Range{0.0, 1.0},
          "rad; U(-reset_noise, reset_noise) added to every IK joint at reset");
  v.choice("observation_layout", c.observation_layout, observation_layout_names(),
           "ground-truth vector: full (target - end effector, end effector - each landmark, end-effector "
           "position, the task's observed links - each landmark) or relative (end effector - target, end "
           "effector - each landmark: RobotDrlSim's)");
}

// The folder holding rdsim's assets: `urdf_root` when set, else repo_root()/assets.
std::string asset_root(const ReachOptions& options);

// An env config with reaching options (a reaching env's defaults): `common` with `options` as its group.
EnvConfig reach_env_config(EnvConfig common, ReachOptions options);

}  // namespace rdsim
