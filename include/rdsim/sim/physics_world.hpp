#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "rdsim/sim/robot.hpp"
#include "rdsim/sim/robot_model.hpp"

// A Bullet Featherstone world (btMultiBodyDynamicsWorld, single precision) holding robots and
// static objects built from RobotModels. Bullet types stay inside src/sim.
//
// Collision filtering (why: only pairs that can matter are ever tested):
//  - static bodies never test against each other, nor against a robot's fixed base;
//  - a robot's links never test against each other (no self-collision) nor other robots';
//  - robot links test against static bodies, broadphase first (AABBs), then narrowphase.
// The broadphase is Bullet's simple one (all AABB pairs, a few dozen objects at most), because its
// pair order depends only on the bodies' current AABBs: after forget_contacts() a world replays
// bit for bit whatever happened before.
namespace rdsim {

struct WorldSettings {
  Eigen::Vector3f gravity{0.0f, 0.0f, -9.8f};
  double time_step = 1.0 / 240.0;  // s, one fixed step per step()
  int solver_iterations = 50;      // Bullet's sequential-impulse iterations per step
  // Stop iterating earlier once the solver's squared residual falls below this (0 = never).
  // Bullet's residual is the largest squared velocity change (m^2/s^2 or rad^2/s^2) any row made in
  // the last iteration; pybullet sets 1e-7.
  double solver_residual_threshold = 0.0;
  // Bullet's btContactSolverInfo defaults; pybullet_solver() gives pybullet's.
  double contact_erp = 0.2;           // share of a contact's penetration corrected per step (erp2)
  double friction_erp = 0.2;          // the same for friction anchors
  double linear_slop = 0.0;           // m of penetration left uncorrected
  double warmstarting_factor = 0.85;  // share of last step's impulses each solve starts from
  // Solve the joint rows (motors, joint limits, couplings) on their non-zero entries only. Exact: the
  // same impulses, bit for bit, as Bullet's dense rows, in a fraction of the time (src/sim/sparse_row_solver.hpp).
  // false = Bullet's own code, kept for the tests that show the two agree.
  bool sparse_joint_rows = true;
  // Each joint row (motor, joint limit) starts the solve from this fraction of the impulse it
  // ended the last step with, instead of from zero (0: Bullet's and pybullet's behaviour). A
  // motor holding an arm needs about the same impulse step after step, so with a residual
  // threshold the solver then stops after a few iterations instead of rebuilding it.
  double joint_row_warm_start = 0.0;
  // Before the iterations, solve one multibody's joint rows (motors, joint limits) together,
  // directly: an LDLT solve of J M^-1 J^T with the rows' bounds kept by an active set, from where
  // warm starting left them (src/sim/sparse_row_solver.cpp). Bullet's Gauss-Seidel iterations
  // then start at the joint rows' fixed point and only polish it and solve the contacts, so with
  // a residual threshold they stop after a few iterations instead of tens to 150 (an arm's joints
  // are strongly coupled: Gauss-Seidel converges slowly on them). Not bit-exact: it ends within
  // the solver's tolerance of where the iterations converge. Skipped (Bullet's iterations alone)
  // when the rows span several bodies or are linearly dependent.
  bool joint_block_solve = false;
  // The unit-impulse responses of a robot's joint rows (motors, joint limits, couplings) from rdsim's
  // own mass matrix, M(q) by composite rigid bodies in double precision factorised once per physics
  // step (the computed-torque drive's own M(q) where it has one), instead of one Bullet
  // articulated-body pass per row (src/sim/joint_rows.hpp). Not bit-exact: Bullet computes its
  // passes in single precision. Robots with welded joints keep Bullet's passes.
  bool mass_matrix_responses = false;
  // Skip Bullet's narrow phase for a box and a convex shape whose broadphase boxes overlap but
  // which are provably farther apart than the contact-breaking threshold, and have no contact
  // points to refresh; and skip the broadphase's pair-cache lookups for pairs the collision filter
  // rules out. Exact: the same simulation bit for bit (src/sim/separated_pairs.hpp,
  // src/sim/filtered_broadphase.hpp); false = Bullet's own collision pass, kept for the tests that
  // show the two agree.
  bool skip_separated_pairs = true;
};

// The solver settings pybullet's physics server applies to every new world (contact ERP 0.08, linear
// slop 1e-5 m, warm starting 0.1, residual threshold 1e-7; Bullet's for the rest), on top of `base`.
WorldSettings pybullet_solver(WorldSettings base);

// One link of one body: `link` indexes the body's RobotModel links (0 for a static body).
struct BodyLink {
  int body = -1;
  int link = -1;
};

struct Contact {
  BodyLink a, b;
  Eigen::Vector3f position_on_a, position_on_b;
  Eigen::Vector3f normal_on_b;  // world frame, from b towards a
  float distance = 0.0f;        // signed; negative = penetration depth
};

// A free body's centre-of-mass frame (Bullet's world transform: rotation row by row, then origin)
// and its velocities (m/s, rad/s).
struct FreeBodyState {
  float transform[12] = {};
  Eigen::Vector3f linear = Eigen::Vector3f::Zero();
  Eigen::Vector3f angular = Eigen::Vector3f::Zero();
};

class PhysicsWorld {
public:
  explicit PhysicsWorld(const WorldSettings& settings = {});
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  // A body that never moves by itself (floor, table, button): every link's collision shapes at
  // the model's zero pose, placed at `pose`. Returns its body id. free_bodies_only: robots pass
  // through it, only free bodies collide with it (a floor for a pushed object where the robot never
  // reaches: no contact tests with every robot link each step).
  int add_static_body(const RobotModel& model, const Eigen::Isometry3f& pose, bool free_bodies_only = false);
  // A free rigid body (a button the arm can push away, as pybullet's): a one-link model's collision
  // shapes with its mass (> 0) and inertia, placed at `pose`; it collides with everything. Bullet's
  // rigid-body defaults (friction 0.5, no restitution, no damping). set_static_pose teleports it at
  // rest, static_pose says where it is now. Returns its body id.
  int add_free_body(const RobotModel& model, const Eigen::Isometry3f& pose);
  // Moves a static (or free) body (e.g. a randomised target) and forgets its cached contacts.
  void set_static_pose(int body, const Eigen::Isometry3f& pose);
  Eigen::Isometry3f static_pose(int body) const;
  bool is_free_body(int body) const;
  // A free body's motion between steps, exactly as Bullet holds it (for saved env states: a pose
  // through static_pose would round). rdsim::Error for a body that is not free.
  FreeBodyState free_body_state(int body) const;
  // A free body's Coulomb friction coefficient (Bullet's default 0.5; a contact's is the product of
  // its two sides'), with friction anchors (Robot::set_link_friction says why). rdsim::Error for a
  // body that is not free or a negative or non-finite value.
  void set_free_body_friction(int body, float friction);
  float free_body_friction(int body) const;
  // A free body's mass and moments as its model gives them times `scale` (> 0; domain
  // randomization: envs/task_randomizer.hpp); each call replaces the last. rdsim::Error for a body
  // that is not free or a scale out of range.
  void set_free_body_mass_scale(int body, double scale);
  double free_body_mass(int body) const;  // kg
  // Puts a free body back in a state free_body_state gave (bit for bit) and forgets its contacts.
  void set_free_body_state(int body, const FreeBodyState& state);

  // A fixed-base articulated robot with its root link at `base_pose`; its body id is robot.body().
  Robot& add_robot(const RobotModel& model, const Eigen::Isometry3f& base_pose, const RobotOptions& options = {});
  Robot& robot(int body);
  const Robot& robot(int body) const;
  int body_count() const;

  void step();  // one fixed time step
  double time() const { return time_; }
  // Work the steps so far have done (benchmarks and tests read it).
  struct Work {
    long long steps = 0;              // step() calls
    long long solver_iterations = 0;  // sequential-impulse iterations, summed over steps
    long long pairs_skipped = 0;      // narrow-phase tests skipped (WorldSettings::skip_separated_pairs)
  };
  Work work() const;
  const WorldSettings& settings() const { return settings_; }

  // Contacts found by the last step's collision pass (points within `max_distance`).
  std::vector<Contact> contacts(float max_distance = 0.0f) const;
  // Whether any contact point between the two (link -1 = any link of that body) is closer than
  // `tolerance` (resting contacts sit at about zero distance). No allocation.
  bool touching(BodyLink a, BodyLink b, float tolerance = 1e-3f) const;
  // Deepest penetration (>= 0, metres) between the two; 0 when they do not touch.
  float penetration(BodyLink a, BodyLink b) const;
  // Drops the cached contact pairs of a body (after teleporting it), so the next step starts
  // from its current state only.
  void forget_contacts(int body);
  // Drops every cached pair and contact manifold (with its warm-starting impulses) and the joint
  // rows' warm starts (WorldSettings::joint_row_warm_start). Afterwards
  // the world evolves exactly like one rebuilt from the same body poses and joint states: the
  // broadphase re-finds pairs in its fixed proxy order. What EnvState::drop_caches relies on.
  void forget_all_contacts();
  // Simulated time, for restoring a saved world (time() as it was).
  void set_time(double seconds) { time_ = seconds; }

  struct Impl;  // the Bullet objects (src/sim/physics_world_impl.hpp), for Robot's implementation
  Impl& impl() { return *impl_; }

private:
  WorldSettings settings_;
  double time_ = 0.0;
  long long steps_ = 0;  // step() calls (Work)
  std::unique_ptr<Impl> impl_;
};

}  // namespace rdsim
