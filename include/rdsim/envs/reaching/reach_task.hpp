#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/sim/kinematics.hpp"
#include "rdsim/sim/physics_world.hpp"

// Shared machinery of every "move an end effector to a target by IK" environment (jaka_button,
// jaka_obstacle, inmoov_tomato): a robot and static bodies in a PhysicsWorld, end-effector moves
// turned into joint position targets by a few warm-started IK iterations, a target point, and the
// distance / workspace / contact checks. Robot-agnostic: an env fills a ReachTaskSpec and adds its
// own observation, reward and termination terms. Nothing here allocates per step.
//
// Frames: everything in ReachTaskSpec and ReachTask is in the WORLD frame; the IK works in the
// robot's root frame and ReachTask converts with the robot's base pose.
namespace rdsim {

// A body that never moves by itself (table, button, column, tree).
struct StaticBodySpec {
  std::string urdf;  // path of the URDF file
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  // A free rigid body the robot can push away (PhysicsWorld::add_free_body: the URDF's one link with
  // its mass), put back at `pose` (or the drawn target) at rest at each reset.
  bool free = false;
  // Only free bodies collide with it (PhysicsWorld::add_static_body's free_bodies_only).
  bool free_bodies_only = false;
};

struct ReachTaskSpec {
  std::string name;        // the env's registry name, for Spec::env_name and messages
  std::string robot_urdf;  // path of the robot's URDF file
  // Folders searched for the robot URDF's package:// and relative mesh paths, in order
  // (load_robot_urdf).
  std::vector<std::string> package_paths;
  Eigen::Isometry3f base_pose = Eigen::Isometry3f::Identity();
  std::string ee_link;          // end-effector link (the IK chain runs from the root link to it)
  // Joints the IK may move (names); empty = every movable joint between the root and ee_link. The
  // other joints on that path keep their home target (the IK sees them frozen at their home value).
  std::vector<std::string> ik_joints;
  Eigen::VectorXf home;         // the task's working pose, one value per robot dof (Robot::dof order)
  // RobotDrlSim's reset pose (one value per dof): where reset_to_rest episodes start and what the
  // null_space IK pulls towards. Empty = home.
  Eigen::VectorXf rest;

  std::vector<StaticBodySpec> statics;
  // Index into `statics` of the body that carries the target (moved with it), -1 for none; the
  // target point is that body's frame moved by `target_offset` (in the body frame). A free target
  // body carries the target along when the robot pushes it.
  int target_body = -1;
  Eigen::Vector3f target_offset = Eigen::Vector3f::Zero();

  Eigen::Vector3f nominal_target = Eigen::Vector3f::Zero();      // target point without randomisation
  Eigen::Vector3f target_half_range = Eigen::Vector3f::Zero();   // random_target: += U(-1,1) * this, per axis
  // random_target draws around this point instead of nominal_target when set.
  std::optional<Eigen::Vector3f> random_centre;
  Eigen::AlignedBox3f workspace;  // move targets are clipped into it; the ee leaving it ends an episode
  // When set, every move also holds the end effector at this orientation (world frame): the IK
  // solves position and orientation together (6 rows, damped least squares; a gripper kept pointing
  // down). Unset: position only, the orientation is whatever the IK leaves.
  std::optional<Eigen::Quaternionf> effector_orientation;

  // Task numbers, from the env's EnvConfig (apply_env_config; envs/reach_options.hpp says what each does):
  bool discrete = true;           // actions: Discrete(6) moves, else a continuous Box(3)
  float step = 0.0f;              // m per discrete move / largest continuous move
  float move_noise = 1.0f / 30.0f;  // Gaussian noise on each move component, sigma = move_noise * step
  float success_threshold = 0.0f;    // m
  float max_distance = 0.0f;         // m from the target: farther ends the episode (workspace_bounds)
  float workspace_margin = 0.03f;    // m the ee may lag outside `workspace` before it counts as out
  bool workspace_bounds = true;      // goals clipped into `workspace`; leaving it or max_distance ends an episode
  int max_steps = 0;
  int action_repeat = 1;             // physics steps per env step
  IkMethod ik_method = IkMethod::DampedLeastSquares;
  int ik_iterations = 1;             // IK steps per move (one FK + Jacobian each), from the current joints
  bool ik_all_joints = false;        // true: every joint on the path root -> ee_link, whatever ik_joints says
  bool reset_to_rest = false;        // episodes start at `rest` instead of `home`
  float reset_noise = 0.0f;          // rad; uniform +-reset_noise added to every IK-chain joint at reset

  // The physics (defaults: the env options' defaults): 1/240 s per physics step, 10 solver
  // iterations (they only resolve contacts: the ComputedTorque drive adds no solver rows, and
  // without limit constraint rows the joint limits hold through the targets, which
  // set_position_targets clamps). drive position_motor: ConstraintMotor with limit constraints.
  WorldSettings world{.time_step = 1.0 / 240.0, .solver_iterations = 10};
  RobotOptions robot{.drive = JointDrive::ComputedTorque, .limit_constraints = false};
};

// Copies the task numbers and physics options of `config` (checked by read_env_config / make_env;
// its ReachOptions group) into `spec`: everything above from is_discrete, action_step, move_noise, success_threshold,
// max_distance, workspace_bounds, max_steps, action_repeat, ik_method, ik_iterations, ik_joints,
// reset_pose, reset_noise, solver_iterations, drive, position_gain and velocity_gain. The
// position_motor drive also turns on the solver savings checked by `rdsim bench-physics`
// (WorldSettings::solver_residual_threshold 1e-9 and joint_row_warm_start 1, RobotOptions::
// weld_held_joints for the joints off the IK chain).
void apply_env_config(const EnvConfig& config, ReachTaskSpec& spec);

// The robot of `spec`: its URDF, with spec.package_paths as the mesh search path.
RobotModel load_robot_urdf(const ReachTaskSpec& spec);

class ReachTask {
public:
  explicit ReachTask(ReachTaskSpec spec);  // loads the URDFs (rdsim::Error on bad files)
  ~ReachTask();
  ReachTask(const ReachTask&) = delete;
  ReachTask& operator=(const ReachTask&) = delete;

  // Reset pose (home or rest, + seeded noise), target at the nominal point or (random_target) drawn
  // from the Rng.
  void reset(Rng& rng, bool random_target);
  // Puts the target at `point` (moving the target body, if any) and forgets its contacts.
  void set_target(const Eigen::Vector3f& point);

  // The actions of every reaching task: Discrete(6) = -x, +x, -y, +y, -z, +z end-effector moves of
  // spec().step; continuous (spec().discrete false) Box(3) of dx, dy, dz in [-1, 1] times spec().step.
  ActionSpace action_space() const;
  // The end-effector move (m, world frame) an action asks for; non-finite box values count as 0,
  // others are clipped to [-1, 1]. rdsim::Error naming the env for an index outside 0..5 or a box
  // action of the wrong size.
  Eigen::Vector3f move_for(const Action& action) const;

  // Joint targets for "end effector + delta" (delta plus Gaussian move noise from `rng`, clipped into
  // the workspace with workspace_bounds), by ik_iterations IK steps from the current joint angles,
  // clamped to the joint limits: damped_least_squares (sim/ik.hpp damped_least_squares_step, damping
  // 0.02 m) or null_space (sim/ik.hpp null_space_ik towards the rest pose). With the ComputedTorque
  // drive the joint step is scaled down as a whole when a joint would exceed its URDF speed limit
  // over one control period (so the move is slowed, never bent); position motors get the IK
  // solution as it is. Does not step physics.
  void apply_move(const Eigen::Vector3f& delta, Rng& rng);
  // The joint targets apply_move would set for `delta` without move noise, one per IK chain joint
  // (chain_dofs() order). For a controller that commands joints (the manipulation expert).
  Eigen::VectorXf move_targets(const Eigen::Vector3f& delta) const;
  // Joint targets that put the end effector at the absolute point `goal` (world frame, clipped
  // into the workspace): damped least squares IK (sim/ik.hpp, up to 100 iterations, 0.1 mm) on the
  // IK chain from the current joint angles, clamped to the limits. No move noise and no speed
  // scaling: the joint drives' speed limits pace the motion over the following steps. Does not
  // step physics. The caller checks that `goal` is finite.
  void apply_effector_target(const Eigen::Vector3f& goal);
  // action_repeat physics steps, then refreshes the end-effector position (and the target point,
  // on a free target body).
  void step_physics();

  // RobotControl's argument checks: rdsim::Error naming `env` for an effector goal that is not
  // finite, or joint targets that are not one finite value per robot dof (RobotInfo::joints order).
  static void check_effector_goal(const Eigen::Vector3f& position, const std::string& env);
  void check_joint_targets(const Eigen::VectorXf& targets, const std::string& env) const;
  // The robot as RobotControl describes it (core/robot_control.hpp): name, effector link, every
  // movable joint with its limits, the workspace box; cameras are the env's to add.
  RobotInfo robot_info() const;
  // Its joints, targets and effector pose now, the target point (steps: the env's to fill in).
  RobotSnapshot robot_snapshot() const;
  const Eigen::Vector3f& ee_position() const { return ee_; }  // world frame, as of the last step/reset
  // The end effector's linear velocity (m/s, world frame) now: the chain's Jacobian times its joint
  // speeds.
  Eigen::Vector3f ee_velocity() const;
  const Eigen::Vector3f& target() const { return target_; }
  float distance() const { return (ee_ - target_).norm(); }
  bool reached() const { return distance() < spec_.success_threshold; }
  // Outside the workspace box (plus margin) or farther than max_distance from the target; never
  // without workspace_bounds.
  bool out_of_bounds() const;
  // Whether any robot link touches static body `index` (index into spec().statics).
  bool robot_touches(int static_index) const;

  // The simulated state between steps (robot joints and their targets, target point, end
  // effector, simulated time, the free bodies' motion), for checkpoints. load_state() leaves the contact caches dropped
  // (drop_caches), as EnvState requires; rdsim::Error naming `source` for bytes of another task.
  void save_state(std::ostream& out) const;
  void load_state(std::istream& in, const std::string& source);
  void drop_caches() { world_->forget_all_contacts(); }

  const ReachTaskSpec& spec() const { return spec_; }
  // For renderers and tests.
  PhysicsWorld& world() { return *world_; }
  const PhysicsWorld& world() const { return *world_; }
  Robot& robot() { return *robot_; }
  const Robot& robot() const { return *robot_; }
  const RobotModel& robot_model() const { return robot_->model(); }
  int ee_link() const { return ee_link_; }
  int static_body(int index) const { return static_ids_[static_cast<size_t>(index)]; }  // PhysicsWorld body id
  const RobotModel& static_model(int index) const { return static_models_[static_cast<size_t>(index)]; }
  const KinematicChain& chain() const { return *chain_; }
  const std::vector<int>& chain_dofs() const { return chain_dofs_; }  // robot dof of each IK chain joint
  // The joint angles episodes start from (before reset noise): spec().home or spec().rest.
  const Eigen::VectorXf& reset_pose() const { return spec_.reset_to_rest ? spec_.rest : spec_.home; }

private:
  // ik_iterations damped-least-squares steps on position and orientation (effector_orientation)
  // from `q` towards `goal_root` (root frame).
  JointVector pose_steps(const Eigen::Vector3d& goal_root, JointVector q) const;
  // apply_move's chain joint targets for the effector at `goal` (world frame, before workspace clipping).
  JointVector move_solution(Eigen::Vector3f goal) const;
  Eigen::Matrix3d root_orientation() const;  // effector_orientation in the root frame

  ReachTaskSpec spec_;
  std::unique_ptr<PhysicsWorld> world_;
  Robot* robot_ = nullptr;
  std::vector<RobotModel> static_models_;
  std::vector<int> static_ids_;
  std::unique_ptr<KinematicChain> chain_;
  std::vector<int> chain_dofs_;  // robot dof of each chain joint
  JointVector max_joint_move_;   // per chain joint: URDF speed limit x control period
  JointVector rest_chain_;       // the rest pose of the chain joints (null_space IK)
  int ee_link_ = -1;
  Eigen::Isometry3f base_inverse_;
  Eigen::VectorXf scratch_q_;    // reset pose, sized once
  Eigen::Vector3f ee_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f target_ = Eigen::Vector3f::Zero();
};

}  // namespace rdsim
