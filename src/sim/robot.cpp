#include "rdsim/sim/robot.hpp"

#include <BulletDynamics/Featherstone/btMultiBodyGearConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/joint_dynamics.hpp"
#include "rdsim/sim/mesh_file.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "physics_world_impl.hpp"
#include "small_cholesky.hpp"
#include "joint_rows.hpp"

namespace rdsim {
namespace {

constexpr double kMovableMinMass = 1e-3;  // kg, for massless links on movable joints
constexpr double kMinMoment = 1e-8;       // kg m^2, smallest principal moment of a massive link
constexpr float kDefaultFriction = 0.5f;  // Bullet's btCollisionObject default
// RobotOptions::coupled_dofs: in Bullet's gear convention a ratio of -1 keeps the two joints equal
constexpr btScalar kCouplingRatio = -1;
constexpr btScalar kCouplingErp = 0.2;  // share of a position difference corrected per step

// The frame Bullet simulates a link in: its centre of mass with principal axes.
struct BodyFrame {
  Eigen::Isometry3d in_link = Eigen::Isometry3d::Identity();  // body frame in the URDF link frame
  double mass = 0.0;
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();
};

// Principal moments (kg m^2, in the URDF inertial frame's axes) that pybullet's loadURDF gives a link
// when it ignores the URDF's tensor: Bullet's calculateLocalInertia of the shapes pybullet builds
// (collision margin 1 mm). One shape at the inertial frame: a box's or a sphere's exact moments, a
// cylinder's (a 32-sided convex hull in pybullet) those of its bounding box grown by 3 mm a side;
// otherwise (several shapes, an offset one, a mesh, none) those of the box around them all grown by
// the margins (Bullet's compound rule; a mesh's box is its convex hull's grown by two margins, as
// Bullet's btConvexHullShape computes its inertia from its margin-grown bounding box). tools/fidelity checks the result
// against pybullet's.
Eigen::Vector3d shape_moments(const Link& link) {
  static constexpr double kMargin = 0.001;  // m: pybullet's URDF collision margin
  const double m = link.inertial.mass;
  const auto box = [m](const Eigen::Vector3d& l) -> Eigen::Vector3d {
    const Eigen::Vector3d sq = l.cwiseProduct(l);
    return Eigen::Vector3d(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()) * (m / 12.0);
  };
  // The box around a shape in its own frame (m).
  const auto bounds = [](const Shape& s) -> Eigen::AlignedBox3d {
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    switch (s.type) {
      case ShapeType::Box: half = s.size / 2.0; break;
      case ShapeType::Cylinder: half = Eigen::Vector3d(s.radius, s.radius, s.length / 2.0) + Eigen::Vector3d::Constant(2.0 * kMargin); break;
      case ShapeType::Sphere: half = Eigen::Vector3d::Constant(s.radius + kMargin); break;
      case ShapeType::Mesh: {
        // The box of all the mesh's vertices (pybullet's hull keeps every one; rdsim's collision hull
        // may be reduced to max_hull_points, whose box is smaller), grown like the cylinder's by two
        // margins a side, three for an OBJ file, which pybullet wraps in one more compound shape
        // (measured with getDynamicsInfo: the KUKA iiwa's STL links the vertices' box + 6 mm with the
        // link compound's margin, the Panda's OBJ links + 8 mm).
        const double margins = mesh_format(s.mesh.file) == MeshFormat::Obj ? 3.0 : 2.0;
        Eigen::AlignedBox3d hull;
        if (s.mesh.mesh)
          for (const Eigen::Vector3f& p : s.mesh.mesh->positions) hull.extend(Eigen::Vector3d(p.cast<double>()));
        else if (s.mesh.hull)
          for (const Eigen::Vector3f& p : s.mesh.hull->points) hull.extend(Eigen::Vector3d(p.cast<double>()));
        if (hull.isEmpty()) hull.extend(Eigen::Vector3d::Zero());
        return Eigen::AlignedBox3d(hull.min().array() - margins * kMargin, hull.max().array() + margins * kMargin);
      }
    }
    return Eigen::AlignedBox3d(-half, half);
  };
  const Eigen::Isometry3d to_inertial = link.inertial.origin.inverse();
  if (link.collisions.size() == 1 && link.collisions[0].type != ShapeType::Mesh &&
      (to_inertial * link.collisions[0].origin).matrix().isIdentity(1e-9)) {
    const Shape& s = link.collisions[0];
    if (s.type == ShapeType::Box) return box(s.size);
    if (s.type == ShapeType::Sphere) return Eigen::Vector3d::Constant(0.4 * m * s.radius * s.radius);
    return box(bounds(s).sizes() + Eigen::Vector3d::Constant(2.0 * kMargin));
  }
  Eigen::AlignedBox3d around(Eigen::Vector3d::Zero());
  if (!link.collisions.empty()) around.setEmpty();
  for (const Shape& s : link.collisions) {
    const Eigen::Isometry3d pose = to_inertial * s.origin;
    const Eigen::AlignedBox3d b = bounds(s);
    const Eigen::Vector3d centre = pose * b.center();
    const Eigen::Vector3d extent = pose.linear().cwiseAbs() * (b.sizes() / 2.0);
    around.extend(Eigen::Vector3d(centre - extent));
    around.extend(Eigen::Vector3d(centre + extent));
  }
  return box(around.sizes() + Eigen::Vector3d::Constant(2.0 * kMargin));
}

BodyFrame body_frame(const Link& link, bool on_movable_joint, bool inertia_from_shapes) {
  BodyFrame f;
  f.mass = link.inertial.mass;
  const Eigen::Matrix3d& inertia = link.inertial.inertia;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  f.moments = inertia_from_shapes ? shape_moments(link) : Eigen::Vector3d(inertia.diagonal());
  const double off_diagonal = std::abs(inertia(0, 1)) + std::abs(inertia(0, 2)) + std::abs(inertia(1, 2));
  if (!inertia_from_shapes && off_diagonal > 1e-12 * std::max(inertia.trace(), 1e-30)) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
    axes = eig.eigenvectors();
    f.moments = eig.eigenvalues();
    if (axes.determinant() < 0.0) axes.col(2) *= -1.0;  // keep a right-handed frame
  }
  if (on_movable_joint && f.mass <= 0.0) {
    f.mass = kMovableMinMass;
    f.moments.setConstant(kMinMoment);
  }
  // Shape-derived moments are pybullet's as they are (a 2 g link without shapes: 1.3e-9 kg m^2).
  if (f.mass > 0.0 && !inertia_from_shapes) f.moments = f.moments.cwiseMax(kMinMoment);
  f.in_link = link.inertial.origin;
  f.in_link.linear() = link.inertial.origin.linear() * axes;
  return f;
}

btQuaternion to_bt(const Eigen::Quaterniond& q) {
  return btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()), static_cast<btScalar>(q.z()),
                      static_cast<btScalar>(q.w()));
}

// Whether nothing can move this link: every joint between it and the (fixed) base is fixed.
bool welded_to_base(const RobotModel& model, int link) {
  for (int l = link; l > 0; l = model.joints[static_cast<size_t>(l - 1)].parent_link)
    if (model.joints[static_cast<size_t>(l - 1)].movable()) return false;
  return true;
}

}  // namespace

// The mass and inertia Bullet simulates each link with (in the link's frame), for rdsim's own
// dynamics of the same robot.
// `mass_scale`: one factor per link on its mass and moments (Robot::set_mass_scales).
static BodyFrame scaled_frame(const RobotModel& model, size_t link, bool inertia_from_shapes, double mass_scale) {
  BodyFrame f = body_frame(model.links[link], link > 0 && model.joints[link - 1].movable(), inertia_from_shapes);
  f.mass *= mass_scale;
  f.moments *= mass_scale;
  return f;
}

static std::vector<Inertial> simulated_inertials(const RobotModel& model, bool inertia_from_shapes,
                                                 const std::vector<double>& mass_scale) {
  std::vector<Inertial> simulated(model.links.size());
  for (size_t i = 0; i < model.links.size(); ++i) {
    const BodyFrame f = scaled_frame(model, i, inertia_from_shapes, mass_scale[i]);
    simulated[i].mass = f.mass;
    simulated[i].inertia = f.moments.asDiagonal();
    simulated[i].origin = f.in_link;
  }
  return simulated;
}

struct Robot::MassResponses {
  JointDynamics dynamics;
  JointResponses out;  // what the joint rows read
  Eigen::VectorXd q;
  Eigen::MatrixXd mass;  // M(q)

  MassResponses(const RobotModel& model, const std::vector<Inertial>& inertials, int dof)
      : dynamics(model, inertials), q(dof), mass(dof, dof) {
    out.velocity_index.assign(static_cast<size_t>(dof), -1);
  }
};

struct Robot::TorqueDrive {
  JointDynamics dynamics;
  Eigen::Vector3d gravity;  // in the root link's frame
  Eigen::VectorXd q, qd, v_target, bias, impulse, limit, v_next, rest, rhs;
  Eigen::MatrixXd mass, mass_inverse, block;
  Eigen::LLT<Eigen::MatrixXd> llt;
  std::vector<int> free_set, clamped_set;  // active-set partition of the joints
  std::vector<signed char> side;           // per joint: 0 free, +1 / -1 impulse at +limit / -limit

  TorqueDrive(const RobotModel& model, const std::vector<Inertial>& inertials, int dof)
      : dynamics(model, inertials), q(dof), qd(dof), v_target(dof), bias(dof), impulse(dof), limit(dof),
        v_next(dof), rest(dof), rhs(dof), mass(dof, dof), mass_inverse(dof, dof), block(dof, dof), llt(dof),
        side(static_cast<size_t>(dof)) {
    free_set.reserve(static_cast<size_t>(dof));
    clamped_set.reserve(static_cast<size_t>(dof));
  }

  // Joint impulses (N m s) over dt that bring the joint speeds to v_target, each within +-limit:
  // the box-constrained problem the motor constraints pose (M positive definite, so its solution is
  // unique), solved exactly when nothing saturates, else by an active set and, should that cycle,
  // by projected Gauss-Seidel on M's inverse.
  void solve_impulses(double dt) {
    impulse.noalias() = mass * (v_target - qd);
    impulse += bias * dt;
    if ((impulse.cwiseAbs().array() <= limit.array()).all()) return;
    if (solve_active_set(dt)) return;
    solve_gauss_seidel(dt);
  }

  // Why an active set: a moving arm saturates a few joints on most steps; the clamped joints' speeds
  // then follow from a |clamped| x |clamped| solve, where Gauss-Seidel needs M's full inverse (for the
  // 54-joint InMoov that inverse was most of a physics step). Returns false if it did not settle.
  bool solve_active_set(double dt) {
    const int n = static_cast<int>(impulse.size());
    rest.noalias() = mass * qd;
    rest -= bias * dt;  // M v_next = rest + impulse
    for (int i = 0; i < n; ++i) side[static_cast<size_t>(i)] = impulse[i] > limit[i] ? 1 : impulse[i] < -limit[i] ? -1 : 0;
    for (int round = 0; round < 2 * n + 2; ++round) {
      free_set.clear();
      clamped_set.clear();
      for (int i = 0; i < n; ++i) (side[static_cast<size_t>(i)] ? clamped_set : free_set).push_back(i);
      const int c = static_cast<int>(clamped_set.size());
      // Clamped joints: impulse at its limit, speed from their rows of M v_next = rest + impulse with the
      // free joints at their target speeds.
      for (int a = 0; a < c; ++a) {
        const int i = clamped_set[static_cast<size_t>(a)];
        impulse[i] = side[static_cast<size_t>(i)] * limit[i];
        double r = rest[i] + impulse[i];
        for (int j : free_set) r -= mass(i, j) * v_target[j];
        rhs[a] = r;
        for (int b = 0; b < c; ++b) block(a, b) = mass(i, clamped_set[static_cast<size_t>(b)]);
      }
      if (c > 0) {
        Eigen::Ref<Eigen::MatrixXd> clamped_block = block.topLeftCorner(c, c);
        Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> factor(clamped_block);  // in place: no allocation
        if (factor.info() != Eigen::Success) return false;
        factor.solveInPlace(rhs.head(c));
      }
      for (int j : free_set) v_next[j] = v_target[j];
      for (int a = 0; a < c; ++a) v_next[clamped_set[static_cast<size_t>(a)]] = rhs[a];
      // Free joints: the impulse their target speed needs.
      for (int i : free_set) impulse[i] = mass.row(i).dot(v_next) - rest[i];
      bool changed = false;
      const double slack = 1e-9;
      for (int i : free_set)
        if (std::abs(impulse[i]) > limit[i] * (1.0 + slack)) {
          side[static_cast<size_t>(i)] = impulse[i] > 0.0 ? 1 : -1;
          changed = true;
        }
      if (changed) continue;
      // A clamped joint whose speed passes its target does not need all of its limit: free it.
      for (int i : clamped_set) {
        const double over = side[static_cast<size_t>(i)] * (v_next[i] - v_target[i]);
        if (over > slack * (1.0 + std::abs(v_target[i]))) {
          side[static_cast<size_t>(i)] = 0;
          changed = true;
        }
      }
      if (!changed) return true;
    }
    return false;
  }

  void solve_gauss_seidel(double dt) {
    impulse.noalias() = mass * (v_target - qd);
    impulse += bias * dt;
    llt.compute(mass);
    mass_inverse.setIdentity();
    llt.solveInPlace(mass_inverse);
    impulse = impulse.cwiseMax(-limit).cwiseMin(limit);
    v_next = qd + mass_inverse * (impulse - bias * dt);
    for (int sweep = 0; sweep < 50; ++sweep) {
      double largest_change = 0.0;
      for (int i = 0; i < impulse.size(); ++i) {
        const double wanted = impulse[i] + (v_target[i] - v_next[i]) / mass_inverse(i, i);
        const double change = std::clamp(wanted, -limit[i], limit[i]) - impulse[i];
        if (change == 0.0) continue;
        impulse[i] += change;
        v_next += mass_inverse.col(i) * change;
        largest_change = std::max(largest_change, std::abs(change));
      }
      if (largest_change < 1e-9) break;
    }
  }
};

Robot::Robot(PhysicsWorld& world, int body, const RobotModel& model, const Eigen::Isometry3f& base_pose,
             const RobotOptions& options)
    : world_(world), body_(body), model_(model), base_pose_(base_pose), options_(options),
      position_gain_(options.position_gain), velocity_gain_(options.velocity_gain) {
  if (model.links.empty()) throw Error(model.source + ": a robot needs at least one link");
  link_friction_.assign(model.links.size(), kDefaultFriction);
  link_anchored_.assign(model.links.size(), false);
  mass_scale_.assign(model.links.size(), 1.0);
  for (size_t i = 1; i < model.links.size(); ++i) {
    const Joint& j = model.joints[i - 1];
    if (!j.movable()) continue;
    Dof d;
    d.joint = static_cast<int>(i) - 1;
    d.bullet_link = static_cast<int>(i) - 1;
    d.lower = static_cast<float>(j.lower);
    d.upper = static_cast<float>(j.upper);
    d.velocity = static_cast<float>(j.velocity);
    d.effort = static_cast<float>(j.effort);
    d.damping = options.joint_damping ? static_cast<float>(j.damping) : 0.0f;
    dofs_.push_back(d);
  }
  // Joint rows exist with motors on every joint, or on the motor dofs and couplings of the
  // computed-torque drive (a gripper's fingers).
  const bool rows = options.drive == JointDrive::ConstraintMotor || !options.motor_dofs.empty() || !options.coupled_dofs.empty();
  if (rows && world.settings().mass_matrix_responses)
    responses_ = std::make_unique<MassResponses>(model, simulated_inertials(model, options.inertia_from_shapes, mass_scale_), dof());
  build();
  if (options.drive == JointDrive::ComputedTorque) {
    const std::vector<Inertial> simulated = simulated_inertials(model, options.inertia_from_shapes, mass_scale_);
    const auto dt = static_cast<btScalar>(world.settings().time_step);  // as Bullet's motors get it
    drive_ = std::make_unique<TorqueDrive>(model, simulated, dof());
    drive_->gravity = base_pose.linear().cast<double>().transpose() * world.settings().gravity.cast<double>();
    for (int i = 0; i < dof(); ++i)  // the motor dofs get no torque from the drive
      drive_->limit[i] = has_motor(i) ? 0.0 : static_cast<double>(dofs_[static_cast<size_t>(i)].effort) * dt;
  }
  // Start at q = 0, or the nearest in-limit position.
  Eigen::VectorXf q0 = Eigen::VectorXf::Zero(dof());
  reset_joints(q0);
}

void Robot::build() {
  PhysicsWorld::Impl& impl = world_.impl();
  const RobotModel& model = model_;
  const size_t n = model.links.size();
  std::vector<BodyFrame> frames(n);
  body_to_link_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    frames[i] = scaled_frame(model, i, options_.inertia_from_shapes, mass_scale_[i]);
    body_to_link_[i] = frames[i].in_link.inverse().cast<float>();
  }
  std::vector<const Dof*> link_dof(n, nullptr);
  for (const Dof& d : dofs_) link_dof[static_cast<size_t>(d.joint) + 1] = &d;

  multibody_ = new btMultiBody(static_cast<int>(n) - 1, static_cast<btScalar>(frames[0].mass), to_bt(frames[0].moments),
                               /*fixedBase=*/true, /*canSleep=*/false);
  multibody_->setBaseWorldTransform(to_bt(Eigen::Isometry3f(base_pose_ * frames[0].in_link.cast<float>())));
  for (size_t i = 1; i < n; ++i) {
    const Joint& j = model.joints[i - 1];
    const BodyFrame& parent = frames[static_cast<size_t>(j.parent_link)];
    const BodyFrame& child = frames[i];
    // A welded joint: its child placed at the joint's target, as the joint itself would place it.
    const Dof* welded = link_dof[i] && link_dof[i]->welded ? link_dof[i] : nullptr;
    Eigen::Isometry3d origin = j.origin;
    if (welded && j.type == JointType::Prismatic) origin = origin * Eigen::Translation3d(welded->target * j.axis);
    if (welded && j.type != JointType::Prismatic) origin = origin * Eigen::AngleAxisd(welded->target, j.axis);
    // Bullet wants, at q = 0: the rotation taking parent-body vectors into child-body vectors,
    // the pivot (joint origin) from the parent's centre of mass in parent-body axes, and the
    // child's centre of mass from the pivot in child-body axes.
    const Eigen::Isometry3d joint_in_parent = parent.in_link.inverse() * origin;
    const Eigen::Isometry3d child_in_parent = joint_in_parent * child.in_link;
    const btQuaternion parent_to_this = to_bt(Eigen::Quaterniond(child_in_parent.linear().transpose()));
    const btVector3 pivot = to_bt(Eigen::Vector3d(joint_in_parent.translation()));
    const btVector3 pivot_to_com = to_bt(Eigen::Vector3d(child.in_link.linear().transpose() * child.in_link.translation()));
    const btVector3 axis = to_bt(Eigen::Vector3d(child.in_link.linear().transpose() * j.axis));
    const int link = static_cast<int>(i) - 1, parent_link = j.parent_link - 1;
    const auto mass = static_cast<btScalar>(child.mass);
    const btVector3 moments = to_bt(child.moments);
    const JointType type = welded ? JointType::Fixed : j.type;
    switch (type) {
      case JointType::Revolute:
      case JointType::Continuous:
        multibody_->setupRevolute(link, mass, moments, parent_link, parent_to_this, axis, pivot, pivot_to_com, true);
        break;
      case JointType::Prismatic:
        multibody_->setupPrismatic(link, mass, moments, parent_link, parent_to_this, axis, pivot, pivot_to_com, true);
        break;
      case JointType::Fixed:
        multibody_->setupFixed(link, mass, moments, parent_link, parent_to_this, pivot, pivot_to_com);
        break;
    }
  }
  multibody_->finalizeMultiDof();
  multibody_->setHasSelfCollision(false);
  multibody_->setCanSleep(false);
  // Bullet's default 0.04 damping would slow every link a little on every step; the motors
  // already damp the arm, so by default the simulated motion is left undamped, as the URDF
  // describes it. pybullet keeps the 0.04 (RobotOptions::link_damping).
  multibody_->setLinearDamping(options_.link_damping);
  multibody_->setAngularDamping(options_.link_damping);
  multibody_->setUserIndex(body_);
  impl.world.addMultiBody(multibody_, kRobotLinkGroup, kRobotLinkMask);

  // Collision groups follow the model, not the welds: a welded link still touches the objects.
  std::vector<std::pair<btMultiBodyLinkCollider*, bool>> new_colliders;  // collider, welded to the base
  for (size_t i = 0; i < n; ++i) {
    std::vector<PlacedShape> placed;
    for (const Shape& s : model.links[i].collisions) placed.push_back({s, frames[i].in_link.inverse() * s.origin});
    btCollisionShape* shape = make_collision_shape(placed, false, impl.shapes);
    if (!shape) continue;
    auto* collider = new btMultiBodyLinkCollider(multibody_, static_cast<int>(i) - 1);
    collider->setCollisionShape(shape);
    collider->setFriction(link_friction_[i] * friction_scale_);
    if (link_anchored_[i]) collider->setCollisionFlags(collider->getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
    collider->setUserIndex(body_);
    collider->setUserIndex2(static_cast<int>(i));
    const bool on_base = welded_to_base(model, static_cast<int>(i));
    if (on_base) collider->setCollisionFlags(collider->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
    if (i == 0)
      multibody_->setBaseCollider(collider);
    else
      multibody_->getLink(static_cast<int>(i) - 1).m_collider = collider;
    colliders_.push_back(collider);
    new_colliders.emplace_back(collider, on_base);
  }
  for (Dof& d : dofs_)  // joint positions before the colliders' first AABBs
    if (!d.welded) multibody_->setJointPos(d.bullet_link, d.target);
  update_transforms();
  for (auto [collider, on_base] : new_colliders)
    impl.world.addCollisionObject(collider, on_base ? kRobotBaseGroup : kRobotLinkGroup,
                                  on_base ? kRobotBaseMask : kRobotLinkMask);

  const auto dt = static_cast<btScalar>(world_.settings().time_step);
  // rdsim's joint constraints set their rows up without the work that yields zeros
  // (src/sim/joint_rows.hpp); Bullet's own go with the reference solver the tests compare them with.
  const bool own_rows = world_.settings().sparse_joint_rows;
  const JointResponses* responses = responses_ ? &responses_->out : nullptr;
  for (Dof& d : dofs_) {
    d.motor = nullptr;
    const int dof = static_cast<int>(&d - dofs_.data());
    if (responses_)
      responses_->out.velocity_index[static_cast<size_t>(dof)] = d.welded ? -1 : 6 + multibody_->getLink(d.bullet_link).m_dofOffset;
    if (d.welded) continue;
    const Joint& j = model.joints[static_cast<size_t>(d.joint)];
    if (options_.drive == JointDrive::ConstraintMotor || has_motor(dof)) {
      const auto max_impulse = static_cast<btScalar>(j.effort) * dt;
      if (own_rows) {
        auto* motor = new JointMotor(multibody_, d.bullet_link, max_impulse);
        motor->use_responses({responses, dof});
        d.motor = motor;
      } else {
        d.motor = new btMultiBodyJointMotor(multibody_, d.bullet_link, 0, 0, max_impulse);
      }
      d.motor->setPositionTarget(d.target, position_gain_);
      d.motor->setVelocityTarget(0, velocity_gain_);
      d.motor->setErp(1);
      if (options_.motor_speed_limits) d.motor->setRhsClamp(static_cast<btScalar>(j.velocity));
      impl.world.addMultiBodyConstraint(d.motor);
    }
    if (options_.limit_constraints && j.type != JointType::Continuous) {
      const auto lower = static_cast<btScalar>(j.lower), upper = static_cast<btScalar>(j.upper);
      btMultiBodyJointLimitConstraint* limit = nullptr;
      if (own_rows) {
        auto* own = new JointLimit(multibody_, d.bullet_link, lower, upper);
        own->use_responses({responses, dof});
        limit = own;
      } else {
        limit = new btMultiBodyJointLimitConstraint(multibody_, d.bullet_link, lower, upper);
      }
      impl.world.addMultiBodyConstraint(limit);
      limits_.push_back(limit);
    }
  }
  for (const auto& [a, b] : options_.coupled_dofs) {
    const Dof& da = dofs_[static_cast<size_t>(a)];
    const Dof& db = dofs_[static_cast<size_t>(b)];
    if (da.welded || db.welded) continue;
    btMultiBodyGearConstraint* gear = nullptr;
    if (own_rows) {
      auto* own = new JointGear(multibody_, da.bullet_link, db.bullet_link);
      own->use_responses({responses, a}, {responses, b});
      gear = own;
    } else {
      gear = new btMultiBodyGearConstraint(multibody_, da.bullet_link, multibody_, db.bullet_link, btVector3(0, 0, 0),
                                           btVector3(0, 0, 0), btMatrix3x3::getIdentity(), btMatrix3x3::getIdentity());
    }
    gear->setGearRatio(kCouplingRatio);
    gear->setErp(kCouplingErp);
    gear->setMaxAppliedImpulse(static_cast<btScalar>(2.0f * std::max(da.effort, db.effort)) * dt);
    impl.world.addMultiBodyConstraint(gear);
    limits_.push_back(gear);
  }
}

void Robot::tear_down() {
  btMultiBodyDynamicsWorld& w = world_.impl().world;
  for (auto& d : dofs_) {
    if (!d.motor) continue;
    w.removeMultiBodyConstraint(d.motor);
    delete d.motor;
    d.motor = nullptr;
  }
  for (auto* l : limits_) {
    w.removeMultiBodyConstraint(l);
    delete l;
  }
  limits_.clear();
  for (auto* c : colliders_) {
    world_.impl().forget_pairs(c);
    w.removeCollisionObject(c);
    delete c;
  }
  colliders_.clear();
  w.removeMultiBody(multibody_);
  delete multibody_;
  multibody_ = nullptr;
}

void Robot::set_welds(const std::vector<bool>& welded) {
  bool change = false;
  for (size_t i = 0; i < dofs_.size(); ++i) change |= dofs_[i].welded != welded[i];
  if (!change) return;
  const RobotState s = state();
  tear_down();
  for (size_t i = 0; i < dofs_.size(); ++i) dofs_[i].welded = welded[i];
  build();
  for (size_t i = 0; i < dofs_.size(); ++i) {
    const Dof& d = dofs_[i];
    if (d.welded) continue;
    multibody_->setJointPos(d.bullet_link, s.positions[i]);
    multibody_->setJointVel(d.bullet_link, s.velocities[i]);
  }
  update_transforms();
}

void Robot::hold(const std::vector<int>& dofs) {
  if (!options_.weld_held_joints || options_.drive != JointDrive::ConstraintMotor) return;
  std::vector<bool> welded = welds();
  for (int i : dofs) {
    if (i < 0 || i >= dof()) throw Error(model_.source + ": hold: no dof " + std::to_string(i));
    const auto k = static_cast<size_t>(i);
    dofs_[k].held = true;
    welded[k] = welded[k] || (joint_position(i) == dofs_[k].target && joint_velocity(i) == 0.0f);
  }
  set_welds(welded);
}

void Robot::free_welds_near_contacts() {
  // Bounding boxes as the broadphase holds them (refreshed by every step and every reset), not its
  // pair cache: that is dropped with the contact caches, and a restored world must free the same
  // joints at the same step as the world it was saved from.
  std::vector<bool> welded;
  for (const btMultiBodyLinkCollider* c : colliders_) {
    const btBroadphaseProxy* proxy = c->getBroadphaseHandle();
    if (!proxy || c->m_link < 0) continue;
    bool near = false;
    for (const auto& s : world_.impl().statics) {
      const btBroadphaseProxy* other = s ? s->getBroadphaseHandle() : nullptr;
      near = near || (other && TestAabbAgainstAabb2(proxy->m_aabbMin, proxy->m_aabbMax, other->m_aabbMin, other->m_aabbMax));
    }
    if (!near) continue;
    for (int l = c->m_link + 1; l > 0; l = model_.joints[static_cast<size_t>(l - 1)].parent_link) {
      const int d = dof_of_joint(l - 1);
      if (d < 0 || !dofs_[static_cast<size_t>(d)].welded) continue;
      if (welded.empty()) welded = welds();
      welded[static_cast<size_t>(d)] = false;
    }
  }
  if (!welded.empty()) set_welds(welded);
}

std::vector<bool> Robot::welds() const {
  std::vector<bool> w;
  for (const Dof& d : dofs_) w.push_back(d.welded);
  return w;
}

int Robot::welded_dofs() const {
  return static_cast<int>(std::count_if(dofs_.begin(), dofs_.end(), [](const Dof& d) { return d.welded; }));
}

Robot::~Robot() { tear_down(); }

int Robot::dof_of_joint(int model_joint) const {
  for (size_t i = 0; i < dofs_.size(); ++i)
    if (dofs_[i].joint == model_joint) return static_cast<int>(i);
  return -1;
}

void Robot::set_position_target(int dof, float q) {
  const float target = std::clamp(q, dofs_[static_cast<size_t>(dof)].lower, dofs_[static_cast<size_t>(dof)].upper);
  if (dofs_[static_cast<size_t>(dof)].welded && target != dofs_[static_cast<size_t>(dof)].target) {
    std::vector<bool> welded = welds();
    welded[static_cast<size_t>(dof)] = false;
    set_welds(welded);
  }
  Dof& d = dofs_[static_cast<size_t>(dof)];
  d.target = target;
  if (d.motor) d.motor->setPositionTarget(d.target, position_gain_);
}

void Robot::set_position_targets(const Eigen::Ref<const Eigen::VectorXf>& q) {
  if (q.size() != dof())
    throw Error(model_.source + ": expected " + std::to_string(dof()) + " joint targets, got " + std::to_string(q.size()));
  for (int i = 0; i < dof(); ++i) set_position_target(i, q[i]);
}

void Robot::set_gains(float position_gain, float velocity_gain) {
  position_gain_ = position_gain;
  velocity_gain_ = velocity_gain;
  for (auto& d : dofs_) {
    if (!d.motor) continue;
    d.motor->setPositionTarget(d.target, position_gain_);
    d.motor->setVelocityTarget(0, velocity_gain_);
  }
}

float Robot::joint_position(int dof) const {
  const Dof& d = dofs_[static_cast<size_t>(dof)];
  return d.welded ? d.target : multibody_->getJointPos(d.bullet_link);
}

float Robot::joint_velocity(int dof) const {
  const Dof& d = dofs_[static_cast<size_t>(dof)];
  return d.welded ? 0.0f : multibody_->getJointVel(d.bullet_link);
}

void Robot::joint_positions(Eigen::Ref<Eigen::VectorXf> out) const {
  for (int i = 0; i < dof(); ++i) out[i] = joint_position(i);
}

Eigen::VectorXf Robot::joint_positions() const {
  Eigen::VectorXf q(dof());
  joint_positions(q);
  return q;
}

Eigen::VectorXf Robot::joint_velocities() const {
  Eigen::VectorXf v(dof());
  for (int i = 0; i < dof(); ++i) v[i] = joint_velocity(i);
  return v;
}

Eigen::VectorXf Robot::position_targets() const {
  Eigen::VectorXf q(dof());
  for (int i = 0; i < dof(); ++i) q[i] = dofs_[static_cast<size_t>(i)].target;
  return q;
}

void Robot::reset_joints(const Eigen::Ref<const Eigen::VectorXf>& q) {
  if (q.size() != dof())
    throw Error(model_.source + ": expected " + std::to_string(dof()) + " joint positions, got " + std::to_string(q.size()));
  // Held joints are welded where they are reset to; any other welded joint sent elsewhere is freed.
  std::vector<bool> welded = welds();
  for (int i = 0; i < dof(); ++i) {
    Dof& d = dofs_[static_cast<size_t>(i)];
    const float qi = std::clamp(q[i], d.lower, d.upper);
    if (d.held) d.target = qi;  // a welded joint's target is where it is welded
    welded[static_cast<size_t>(i)] = d.held || (d.welded && qi == d.target);
  }
  set_welds(welded);
  for (int i = 0; i < dof(); ++i) {
    Dof& d = dofs_[static_cast<size_t>(i)];
    if (d.welded) continue;
    const float qi = std::clamp(q[i], d.lower, d.upper);
    multibody_->setJointPos(d.bullet_link, qi);
    multibody_->setJointVel(d.bullet_link, 0);
    d.target = qi;
    if (d.motor) d.motor->setPositionTarget(qi, position_gain_);
  }
  multibody_->clearVelocities();
  multibody_->clearForcesAndTorques();
  multibody_->clearConstraintForces();
  update_transforms();
  for (auto* c : colliders_) world_.impl().forget_pairs(c);
}

RobotState Robot::state() const {
  RobotState s;
  for (int i = 0; i < dof(); ++i) {
    s.positions.push_back(joint_position(i));
    s.velocities.push_back(joint_velocity(i));
    s.targets.push_back(dofs_[static_cast<size_t>(i)].target);
  }
  return s;
}

void Robot::set_state(const RobotState& s, const std::string& source) {
  const auto n = static_cast<size_t>(dof());
  if (s.positions.size() != n || s.velocities.size() != n || s.targets.size() != n)
    throw Error(source + ": robot state has " + std::to_string(s.positions.size()) + " joints, " + model_.source +
                " has " + std::to_string(n));
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(s.positions[i]) || !std::isfinite(s.velocities[i]) || !std::isfinite(s.targets[i]))
      throw Error(source + ": robot state of joint " + model_.joints[static_cast<size_t>(dofs_[i].joint)].name +
                  " is not finite");
  std::vector<bool> welded = welds();  // a welded joint given another state is freed
  for (size_t i = 0; i < n; ++i)
    welded[i] = welded[i] && s.positions[i] == dofs_[i].target && s.targets[i] == dofs_[i].target &&
                s.velocities[i] == 0.0f;
  set_welds(welded);
  for (size_t i = 0; i < n; ++i) {
    Dof& d = dofs_[i];
    if (d.welded) continue;
    multibody_->setJointPos(d.bullet_link, s.positions[i]);
    multibody_->setJointVel(d.bullet_link, s.velocities[i]);
    d.target = s.targets[i];
    if (d.motor) d.motor->setPositionTarget(d.target, position_gain_);
  }
  multibody_->clearForcesAndTorques();
  multibody_->clearConstraintForces();
  update_transforms();
}

void Robot::update_transforms() {
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  multibody_->forwardKinematics(world_to_local, local_origin);
  multibody_->updateCollisionObjectWorldTransforms(world_to_local, local_origin);
  btMultiBodyDynamicsWorld& w = world_.impl().world;
  for (auto* c : colliders_)
    if (c->getBroadphaseHandle()) w.updateSingleAabb(c);
}

void Robot::before_step() {
  if (std::any_of(dofs_.begin(), dofs_.end(), [](const Dof& d) { return d.welded; })) free_welds_near_contacts();
  for (const Dof& d : dofs_)
    if (d.damping > 0.0f && !d.welded) multibody_->addJointTorque(d.bullet_link, -d.damping * multibody_->getJointVel(d.bullet_link));
  if (!drive_) {
    if (responses_) update_responses(nullptr);
    return;
  }
  TorqueDrive& t = *drive_;
  const double dt = world_.settings().time_step;
  for (int i = 0; i < dof(); ++i) {
    const Dof& d = dofs_[static_cast<size_t>(i)];
    const double q = multibody_->getJointPos(d.bullet_link), qd = multibody_->getJointVel(d.bullet_link);
    t.q[i] = q;
    t.qd[i] = qd;
    // Bullet's motor law (btMultiBodyJointMotor), so both drives aim at the same speed.
    const double v = position_gain_ * (d.target - q) / dt + qd + velocity_gain_ * (0.0 - qd);
    t.v_target[i] = std::clamp(v, -static_cast<double>(d.velocity), static_cast<double>(d.velocity));
  }
  t.dynamics.mass_matrix_and_bias(t.q, t.qd, t.gravity, t.mass, t.bias);
  if (responses_) update_responses(&t.mass);  // the same M(q), for the motor dofs' and couplings' rows
  t.solve_impulses(dt);
  for (int i = 0; i < dof(); ++i)
    multibody_->addJointTorque(dofs_[static_cast<size_t>(i)].bullet_link, static_cast<btScalar>(t.impulse[i] / dt));
}

void Robot::update_responses(const Eigen::MatrixXd* mass) {
  MassResponses& r = *responses_;
  r.out.valid = false;  // welded joints: Bullet's multibody has fewer dofs than the model
  if (std::any_of(dofs_.begin(), dofs_.end(), [](const Dof& d) { return d.welded; })) return;
  if (!mass) {
    for (int i = 0; i < dof(); ++i) r.q[i] = multibody_->getJointPos(dofs_[static_cast<size_t>(i)].bullet_link);
    r.dynamics.mass_matrix(r.q, r.mass);
    mass = &r.mass;
  }
  r.out.set_mass(*mass);
}

Robot::LinkInertia Robot::link_inertia(int link) const {
  if (link < 0 || link >= static_cast<int>(model_.links.size()))
    throw Error(model_.source + ": link " + std::to_string(link) + " out of range (0.." +
                std::to_string(model_.links.size() - 1) + ")");
  const size_t l = static_cast<size_t>(link);
  const BodyFrame f = scaled_frame(model_, l, options_.inertia_from_shapes, mass_scale_[l]);
  return {f.mass, f.moments};
}

void Robot::set_mass_scales(const std::vector<double>& scales) {
  if (scales.size() != model_.links.size())
    throw Error(model_.source + ": expected " + std::to_string(model_.links.size()) + " mass scales, got " +
                std::to_string(scales.size()));
  for (double s : scales)
    if (!(s > 0.0) || !std::isfinite(s)) throw Error(model_.source + ": a mass scale must be a finite number > 0");
  if (scales == mass_scale_) return;
  mass_scale_ = scales;
  for (size_t i = 1; i < model_.links.size(); ++i) {  // the fixed base's mass never acts
    const BodyFrame f = scaled_frame(model_, i, options_.inertia_from_shapes, mass_scale_[i]);
    btMultibodyLink& link = multibody_->getLink(static_cast<int>(i) - 1);  // Debian's Bullet has no setters
    link.m_mass = static_cast<btScalar>(f.mass);
    link.m_inertiaLocal = to_bt(f.moments);
  }
  // rdsim's own dynamics of the robot (the drive's and the joint rows' M(q)) follow the masses.
  const std::vector<Inertial> simulated = simulated_inertials(model_, options_.inertia_from_shapes, mass_scale_);
  if (drive_) drive_->dynamics = JointDynamics(model_, simulated);
  if (responses_) responses_->dynamics = JointDynamics(model_, simulated);
}

void Robot::set_friction_scale(float scale) {
  if (!(scale >= 0.0f) || !std::isfinite(scale))
    throw Error(model_.source + ": the friction scale must be a finite number >= 0, got " + std::to_string(scale));
  friction_scale_ = scale;
  for (btMultiBodyLinkCollider* c : colliders_) c->setFriction(link_friction_[static_cast<size_t>(c->getUserIndex2())] * scale);
}

void Robot::set_joint_damping(int dof, float damping) {
  if (dof < 0 || dof >= this->dof()) throw Error(model_.source + ": no dof " + std::to_string(dof) + " to damp");
  if (!(damping >= 0.0f) || !std::isfinite(damping))
    throw Error(model_.source + ": joint damping must be a finite number >= 0, got " + std::to_string(damping));
  dofs_[static_cast<size_t>(dof)].damping = damping;
}

float Robot::joint_damping(int dof) const { return dofs_[static_cast<size_t>(dof)].damping; }

bool Robot::has_motor(int dof) const {
  return std::find(options_.motor_dofs.begin(), options_.motor_dofs.end(), dof) != options_.motor_dofs.end();
}

void Robot::set_link_friction(int link, float friction) {
  if (link < 0 || static_cast<size_t>(link) >= model_.links.size())
    throw Error(model_.source + ": no link " + std::to_string(link) + " to set the friction of");
  if (!(friction >= 0.0f) || !std::isfinite(friction))
    throw Error(model_.source + ": link " + model_.links[static_cast<size_t>(link)].name +
                ": friction must be a finite number >= 0, got " + std::to_string(friction));
  link_friction_[static_cast<size_t>(link)] = friction;
  link_anchored_[static_cast<size_t>(link)] = true;
  for (btMultiBodyLinkCollider* c : colliders_)
    if (c->getUserIndex2() == link) {
      c->setFriction(friction * friction_scale_);
      c->setCollisionFlags(c->getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
    }
}

Eigen::Isometry3f Robot::link_pose(int link) const {
  if (link == 0) return from_bt(multibody_->getBaseWorldTransform()) * body_to_link_[0];
  if (const btMultiBodyLinkCollider* c = multibody_->getLink(link - 1).m_collider)
    return from_bt(c->getWorldTransform()) * body_to_link_[static_cast<size_t>(link)];
  // No collider to read: chain from the parent through this joint.
  const Joint& j = model_.joints[static_cast<size_t>(link - 1)];
  Eigen::Isometry3f pose = link_pose(j.parent_link) * j.origin.cast<float>();
  if (j.movable()) {
    const float q = joint_position(dof_of_joint(link - 1));
    const Eigen::Vector3f axis = j.axis.cast<float>();
    if (j.type == JointType::Prismatic)
      pose.translation() += pose.linear() * (axis * q);
    else
      pose.linear() = pose.linear() * Eigen::AngleAxisf(q, axis).toRotationMatrix();
  }
  return pose;
}

}  // namespace rdsim
