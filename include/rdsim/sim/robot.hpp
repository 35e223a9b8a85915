#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rdsim/sim/robot_model.hpp"

class btMultiBody;
class btMultiBodyJointMotor;
class btMultiBodyLinkCollider;
class btMultiBodyConstraint;

// One articulated robot simulated in a PhysicsWorld (a Bullet btMultiBody with a fixed base),
// position-controlled like PyBullet's POSITION_CONTROL: each movable joint is driven towards
// the joint speed
//     v* = clamp(kp * (target - q) / dt + qdot + kd * (0 - qdot),  +-URDF velocity limit)
// with at most the URDF effort. Two drives implement this law (RobotOptions::drive):
//  - ComputedTorque (default): before every physics step the torques that give exactly v* at the
//    end of the step are computed from the robot's own joint-space dynamics (JointDynamics: mass
//    matrix and gravity/Coriolis bias), clipped to the efforts as a box-constrained problem, and
//    applied as joint torques; Bullet then integrates them with contacts. In free motion this is
//    the converged solution of the motor constraints below; at a contact the drive reacts one
//    step later. It costs about one Bullet articulated-body pass, where every motor row costs one.
//  - ConstraintMotor: Bullet btMultiBodyJointMotor constraints solved together with contacts by
//    the sequential-impulse solver (what PyBullet does); about twice as expensive per step.
//
// Joints are addressed by "dof": the model's movable joints in tree order (dof_joint(i) gives the
// RobotModel joint index). Links are addressed by their RobotModel link index.
//
// Modelling choices (documented because Bullet needs them):
//  - each link's inertia tensor is diagonalised: Bullet bodies live in their principal axes;
//  - a movable joint's child with no mass gets 1 g and a tiny inertia (Bullet cannot move a
//    massless body); the URDF's principal moments below 1e-8 kg m^2 are raised to it (moments
//    from the shapes, RobotOptions::inertia_from_shapes, are kept as pybullet computes them);
//  - URDF joint damping/friction are not simulated (the drives dominate them); Bullet's default
//    link damping is switched off unless RobotOptions::link_damping asks for it (pybullet keeps it).
namespace rdsim {

class PhysicsWorld;

enum class JointDrive { ComputedTorque, ConstraintMotor };

struct RobotOptions {
  JointDrive drive = JointDrive::ConstraintMotor;
  float position_gain = 1.0f;  // kp: 1 asks to close the whole position error within one step
  float velocity_gain = 1.0f;  // kd
  // Joint position limits as Bullet limit constraints (two more solver rows per joint, each as
  // costly as a motor row). Without them the limits hold through the targets, which
  // set_position_targets clamps, and the drive's effort.
  bool limit_constraints = true;
  // ConstraintMotor: clamp the motors' speed target to the URDF velocity limit (pybullet does only
  // when setJointMotorControl2 gets maxVelocity; setJointMotorControlArray cannot give one). The
  // ComputedTorque drive always clamps.
  bool motor_speed_limits = true;
  // Bullet's link damping (btMultiBody linear and angular damping, 1/s): pybullet keeps Bullet's
  // default 0.04; 0 leaves the motion undamped, as the URDF describes it.
  float link_damping = 0.0f;
  // Inertia tensors as pybullet's loadURDF makes them without URDF_USE_INERTIA_FROM_FILE (how
  // RobotDrlSim loaded its robots): the URDF's mass and inertial frame, principal moments from the
  // collision shapes (robot.cpp shape_moments); false: the URDF's tensors.
  bool inertia_from_shapes = false;
  // The URDF's <dynamics damping> (N m s/rad, N s/m for prismatic joints) as pybullet applies it:
  // a joint torque of -damping x joint velocity added before every physics step (explicit, so a
  // light link with a large damping overshoots, as in pybullet). false: the damping is ignored.
  bool joint_damping = false;
  // Joints named by hold() are simulated as welded (Bullet fixed joints at their target) while
  // nothing can move them: no motor row and no degree of freedom for the solver. Why: a position
  // motor resting at its target holds its joint still to within the solver's tolerance, and the
  // InMoov's 46 joints off the reaching path were most of its step's work. A welded joint is freed
  // (the multibody rebuilt, keeping every joint's state) before a step when a link it carries is
  // near a static body (their bounding boxes, grown by Bullet's 2 cm contact margin, overlap:
  // the contact could push it), and by any target, reset or state that moves it; reset_joints
  // welds the held joints again. ConstraintMotor drive only.
  bool weld_held_joints = false;
  // Dofs driven by Bullet joint motors whatever `drive` says (a gripper's fingers): a motor is solved
  // together with the contacts, so fingers closed on an object squeeze it with up to their URDF
  // effort; the ComputedTorque drive, blind to contacts, would press with only the force that moves
  // the free finger. The ComputedTorque drive leaves these dofs alone.
  std::vector<int> motor_dofs{};
  // Pairs of dofs held at equal positions by a gear constraint (Bullet's law; a gripper's two fingers:
  // the mimic joint of a real gripper's linkage), so a squeezed object stays centred between them.
  std::vector<std::pair<int, int>> coupled_dofs{};
};

// Everything a Robot simulates between steps, per dof, as Bullet holds it (floats): joint
// positions, joint velocities and position targets. (Forces are cleared by every step; contact
// caches belong to the world: PhysicsWorld::forget_all_contacts.)
struct RobotState {
  std::vector<float> positions, velocities, targets;
};

class Robot {
public:
  // Built by PhysicsWorld::add_robot.
  Robot(PhysicsWorld& world, int body, const RobotModel& model, const Eigen::Isometry3f& base_pose,
        const RobotOptions& options);
  ~Robot();
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;

  int body() const { return body_; }
  const RobotModel& model() const { return model_; }
  int dof() const { return static_cast<int>(dofs_.size()); }
  int dof_joint(int dof) const { return dofs_[static_cast<size_t>(dof)].joint; }
  int dof_of_joint(int model_joint) const;  // -1 for fixed joints

  // Position targets for every dof (clamped to the joint limits).
  void set_position_targets(const Eigen::Ref<const Eigen::VectorXf>& q);
  void set_position_target(int dof, float q);
  void set_gains(float position_gain, float velocity_gain);

  float joint_position(int dof) const;
  float joint_velocity(int dof) const;
  void joint_positions(Eigen::Ref<Eigen::VectorXf> out) const;
  Eigen::VectorXf joint_positions() const;
  Eigen::VectorXf joint_velocities() const;
  // The drive's current position targets (after clamping), one per dof.
  Eigen::VectorXf position_targets() const;

  RobotState state() const;
  // Puts the joints exactly where state() found them (bit for bit) and refreshes link poses.
  // rdsim::Error naming `source` when the sizes do not match this robot or a value is not finite.
  void set_state(const RobotState& state, const std::string& source);

  // Teleports the joints to `q` at rest (targets = q) and forgets cached contacts.
  void reset_joints(const Eigen::Ref<const Eigen::VectorXf>& q);

  // With RobotOptions::weld_held_joints (and the ConstraintMotor drive): these dofs only ever hold
  // their target; those at rest on it are welded now (and again by each reset_joints).
  // Otherwise does nothing.
  void hold(const std::vector<int>& dofs);
  int welded_dofs() const;

  // A link's URDF frame in the world, as of the last step or reset. Cheap (one transform product).
  Eigen::Isometry3f link_pose(int link) const;

  // The mass (kg) and principal moments (kg m^2) Bullet simulates a link with: the URDF's, or with
  // RobotOptions::inertia_from_shapes those pybullet's loadURDF derives from the collision shapes.
  struct LinkInertia {
    double mass = 0.0;
    Eigen::Vector3d moments = Eigen::Vector3d::Zero();
  };
  LinkInertia link_inertia(int link) const;

  // Coulomb friction coefficient of a link's collision shapes (Bullet's default 0.5). Bullet
  // combines the two sides of a contact by their product (a gripper's pads at 1.0 on a cube at 1.0
  // hold with 1.0). The link's contacts also keep friction anchors (Bullet's
  // CF_HAS_FRICTION_ANCHOR: friction holds each contact where it started instead of only damping
  // its sliding, so a held object does not creep out of the fingers). Kept across the multibody's
  // rebuilds (weld_held_joints). rdsim::Error for a link index out of range or a negative or
  // non-finite coefficient.
  void set_link_friction(int link, float friction);
  float link_friction(int link) const { return link_friction_[static_cast<size_t>(link)]; }

  // Domain randomization (envs/task_randomizer.hpp) varies the simulated robot with these:
  //  - set_mass_scales: one factor per model link (> 0) on its mass and principal moments, in
  //    Bullet and in rdsim's own dynamics of the robot (the ComputedTorque drive's model);
  //  - set_friction_scale: one factor (>= 0) on every link's friction coefficient;
  //  - set_joint_damping: a dof's viscous damping (N m s/rad, N s/m for prismatic joints; >= 0), a
  //    torque of -damping x joint velocity before every physics step. Starts at the URDF's with
  //    RobotOptions::joint_damping, else 0.
  // Each setting replaces the last (never compounds) and survives the multibody's rebuilds.
  // rdsim::Error for a wrong count, a dof out of range or a value out of range.
  void set_mass_scales(const std::vector<double>& scales);
  void set_friction_scale(float scale);
  void set_joint_damping(int dof, float damping);
  float joint_damping(int dof) const;
  float position_gain() const { return position_gain_; }
  float velocity_gain() const { return velocity_gain_; }

  // Called by PhysicsWorld::step before Bullet's step: applies the ComputedTorque drive.
  void before_step();

private:
  struct Dof {
    int joint = -1;        // RobotModel joint
    int bullet_link = -1;  // btMultiBody link index
    float lower = 0, upper = 0;
    float target = 0;
    float velocity = 0, effort = 0;  // URDF limits
    float damping = 0;               // N m s/rad: URDF <dynamics damping> (joint_damping), set_joint_damping
    bool held = false;               // named by hold()
    bool welded = false;             // a Bullet fixed joint at `target` (RobotOptions::weld_held_joints)
    btMultiBodyJointMotor* motor = nullptr;
  };

  PhysicsWorld& world_;
  int body_;
  RobotModel model_;
  Eigen::Isometry3f base_pose_;
  RobotOptions options_;
  btMultiBody* multibody_ = nullptr;
  std::vector<Dof> dofs_;
  std::vector<btMultiBodyLinkCollider*> colliders_;
  std::vector<float> link_friction_;  // per model link (set_link_friction)
  std::vector<bool> link_anchored_;   // per model link: friction anchors on (set_link_friction)
  std::vector<double> mass_scale_;    // per model link (set_mass_scales)
  float friction_scale_ = 1.0f;       // on every link's friction (set_friction_scale)
  std::vector<btMultiBodyConstraint*> limits_;  // joint limits and couplings (coupled_dofs)
  // Per model link: its URDF frame in the frame Bullet simulates (principal axes at the centre of mass).
  std::vector<Eigen::Isometry3f> body_to_link_;
  float position_gain_, velocity_gain_;
  struct TorqueDrive;  // scratch of the ComputedTorque drive (robot.cpp)
  std::unique_ptr<TorqueDrive> drive_;
  struct MassResponses;  // the joint rows' responses, WorldSettings::mass_matrix_responses (robot.cpp)
  std::unique_ptr<MassResponses> responses_;

  void update_transforms();
  bool has_motor(int dof) const;  // named by RobotOptions::motor_dofs
  // M(q)^-1 for the joint rows, before a step (WorldSettings::mass_matrix_responses), from `mass`
  // (the drive's M(q), computed this step) or, without it, computed here.
  void update_responses(const Eigen::MatrixXd* mass);
  // The Bullet objects for the current dofs_ (welded ones as fixed joints), and their removal.
  void build();
  void tear_down();
  // Welds exactly the dofs marked here (at their targets); when that changes anything, the
  // multibody is rebuilt keeping every joint's state.
  void set_welds(const std::vector<bool>& welded);
  std::vector<bool> welds() const;
  // Frees the welded joints that carry a link whose bounding box overlaps a static body's.
  void free_welds_near_contacts();
};

}  // namespace rdsim
