#include "rdsim/sim/physics_world.hpp"

#include <BulletCollision/CollisionShapes/btEmptyShape.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

#include "rdsim/core/error.hpp"
#include "physics_world_impl.hpp"

namespace rdsim {
namespace {

bool is_part_of(const btCollisionObject* o, BodyLink who) {
  return o->getUserIndex() == who.body && (who.link < 0 || o->getUserIndex2() == who.link);
}

BodyLink body_link(const btCollisionObject* o) { return BodyLink{o->getUserIndex(), o->getUserIndex2()}; }

// Calls f(point) for every contact point between a and b (either way round).
template <class F>
void for_each_point(const btCollisionDispatcher& dispatcher, BodyLink a, BodyLink b, F&& f) {
  const int n = dispatcher.getNumManifolds();
  for (int i = 0; i < n; ++i) {
    const btPersistentManifold* m = dispatcher.getManifoldByIndexInternal(i);
    const int points = m->getNumContacts();
    if (points == 0) continue;
    const bool direct = is_part_of(m->getBody0(), a) && is_part_of(m->getBody1(), b);
    const bool swapped = !direct && is_part_of(m->getBody0(), b) && is_part_of(m->getBody1(), a);
    if (!direct && !swapped) continue;
    for (int k = 0; k < points; ++k) f(m->getContactPoint(k));
  }
}

}  // namespace

PhysicsWorld::Impl::~Impl() {
  robots.clear();  // each Robot takes its Bullet objects out of `world`
  for (auto& s : statics)
    if (s && s->getBroadphaseHandle()) world.removeCollisionObject(s.get());
}

void PhysicsWorld::Impl::forget_pairs(btCollisionObject* object) {
  if (btBroadphaseProxy* proxy = object->getBroadphaseHandle())
    broadphase.getOverlappingPairCache()->removeOverlappingPairsContainingProxy(proxy, &dispatcher);
}

PhysicsWorld::PhysicsWorld(const WorldSettings& settings) : settings_(settings), impl_(std::make_unique<Impl>()) {
  if (!(settings.time_step > 0.0)) throw Error("physics: time_step must be > 0");
  if (settings.solver_iterations < 1) throw Error("physics: solver_iterations must be >= 1");
  if (!(settings.joint_row_warm_start >= 0.0 && settings.joint_row_warm_start <= 1.0))
    throw Error("physics: joint_row_warm_start must be in [0, 1]");
  if (!(settings.warmstarting_factor >= 0.0 && settings.warmstarting_factor <= 1.0))
    throw Error("physics: warmstarting_factor must be in [0, 1]");
  impl_->world.setGravity(to_bt(settings.gravity));
  btContactSolverInfo& info = impl_->world.getSolverInfo();
  info.m_numIterations = settings.solver_iterations;
  info.m_leastSquaresResidualThreshold = static_cast<btScalar>(settings.solver_residual_threshold);
  info.m_timeStep = static_cast<btScalar>(settings.time_step);
  info.m_erp2 = static_cast<btScalar>(settings.contact_erp);
  info.m_frictionERP = static_cast<btScalar>(settings.friction_erp);
  info.m_linearSlop = static_cast<btScalar>(settings.linear_slop);
  info.m_warmstartingFactor = static_cast<btScalar>(settings.warmstarting_factor);
  impl_->solver.set_sparse(settings.sparse_joint_rows);
  impl_->solver.set_warm_start(settings.joint_row_warm_start);
  impl_->solver.set_block_solve(settings.joint_block_solve);
  if (settings.skip_separated_pairs) impl_->dispatcher.setNearCallback(skip_separated_pairs);
  impl_->broadphase.set_filter_first(settings.skip_separated_pairs);
}

WorldSettings pybullet_solver(WorldSettings base) {
  base.contact_erp = 0.08;
  base.friction_erp = 0.2;
  base.linear_slop = 1e-5;
  base.warmstarting_factor = 0.1;
  base.solver_residual_threshold = 1e-7;
  return base;
}

PhysicsWorld::~PhysicsWorld() { impl_->robots.clear(); }

int PhysicsWorld::add_static_body(const RobotModel& model, const Eigen::Isometry3f& pose, bool free_bodies_only) {
  const int body = body_count();
  const std::vector<Eigen::Isometry3d> frames = model.link_poses_at_zero();
  std::vector<PlacedShape> placed;
  for (size_t l = 0; l < model.links.size(); ++l)
    for (const Shape& s : model.links[l].collisions) placed.push_back({s, frames[l] * s.origin});

  // One shape: its offset goes into the object's transform instead of a compound shape.
  Eigen::Isometry3f offset = Eigen::Isometry3f::Identity();
  if (placed.size() == 1) {
    offset = placed[0].pose.cast<float>();
    placed[0].pose.setIdentity();
  }
  auto object = std::make_unique<btCollisionObject>();
  btCollisionShape* shape = make_collision_shape(placed, true, impl_->shapes);
  const bool collides = shape != nullptr;
  if (!collides) {  // visual-only decoration: keeps its id and pose, never collides
    impl_->shapes.push_back(std::make_unique<btEmptyShape>());
    shape = impl_->shapes.back().get();
  }
  object->setCollisionShape(shape);
  object->setWorldTransform(to_bt(Eigen::Isometry3f(pose * offset)));
  object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
  object->setUserIndex(body);
  object->setUserIndex2(0);
  if (collides)
    impl_->world.addCollisionObject(object.get(), kStaticGroup, free_bodies_only ? kFreeBodyGroup : kStaticMask);
  impl_->statics.push_back(std::move(object));
  impl_->static_offsets.push_back(offset);
  impl_->robots.push_back(nullptr);
  return body;
}

int PhysicsWorld::add_free_body(const RobotModel& model, const Eigen::Isometry3f& pose) {
  if (model.links.size() != 1) throw Error(model.source + ": a free body must be one link, it has " + std::to_string(model.links.size()));
  const Inertial& inertial = model.links[0].inertial;
  if (!(inertial.mass > 0.0)) throw Error(model.source + ": a free body needs a mass > 0");
  // Bullet moves a rigid body about its centre of mass in its principal axes.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertial.inertia);
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) *= -1.0;
  Eigen::Isometry3d com = inertial.origin;
  com.linear() = inertial.origin.linear() * axes;
  std::vector<PlacedShape> placed;
  for (const Shape& shape : model.links[0].collisions) placed.push_back({shape, com.inverse() * shape.origin});
  btCollisionShape* shape = make_collision_shape(placed, false, impl_->shapes);
  if (!shape) throw Error(model.source + ": a free body needs a collision shape");
  const Eigen::Vector3d moments = eig.eigenvalues().cwiseMax(1e-8);
  btRigidBody::btRigidBodyConstructionInfo info(static_cast<btScalar>(inertial.mass), nullptr, shape, to_bt(moments));
  auto object = std::make_unique<btRigidBody>(info);
  const Eigen::Isometry3f offset = com.cast<float>();
  object->setWorldTransform(to_bt(Eigen::Isometry3f(pose * offset)));
  object->setActivationState(DISABLE_DEACTIVATION);
  const int body = body_count();
  object->setUserIndex(body);
  object->setUserIndex2(0);
  impl_->world.addRigidBody(object.get(), kFreeBodyGroup, btBroadphaseProxy::AllFilter);
  impl_->statics.push_back(std::move(object));
  impl_->static_offsets.push_back(offset);
  impl_->robots.push_back(nullptr);
  impl_->free_masses.resize(impl_->statics.size(), Eigen::Vector4d::Zero());
  impl_->free_masses.back() << inertial.mass, moments;
  return body;
}

void PhysicsWorld::set_static_pose(int body, const Eigen::Isometry3f& pose) {
  if (body < 0 || body >= body_count() || !impl_->statics[static_cast<size_t>(body)])
    throw Error("physics: body " + std::to_string(body) + " is not a static body");
  btCollisionObject* o = impl_->statics[static_cast<size_t>(body)].get();
  o->setWorldTransform(to_bt(Eigen::Isometry3f(pose * impl_->static_offsets[static_cast<size_t>(body)])));
  if (btRigidBody* free = btRigidBody::upcast(o)) {  // teleported at rest
    free->setLinearVelocity(btVector3(0, 0, 0));
    free->setAngularVelocity(btVector3(0, 0, 0));
    free->setCenterOfMassTransform(o->getWorldTransform());  // and its world inertia turned with it
    free->clearForces();
  }
  if (o->getBroadphaseHandle()) {
    impl_->world.updateSingleAabb(o);
    impl_->forget_pairs(o);
  }
}

Eigen::Isometry3f PhysicsWorld::static_pose(int body) const {
  if (body < 0 || body >= body_count() || !impl_->statics[static_cast<size_t>(body)])
    throw Error("physics: body " + std::to_string(body) + " is not a static body");
  return from_bt(impl_->statics[static_cast<size_t>(body)]->getWorldTransform()) *
         impl_->static_offsets[static_cast<size_t>(body)].inverse();
}

namespace {

// The free body `body`, or nullptr for any other id.
btRigidBody* find_free_body(const PhysicsWorld::Impl& impl, int body) {
  btCollisionObject* o = body >= 0 && static_cast<size_t>(body) < impl.statics.size() ? impl.statics[static_cast<size_t>(body)].get() : nullptr;
  return o ? btRigidBody::upcast(o) : nullptr;
}

btRigidBody* free_body_of(const PhysicsWorld::Impl& impl, int body) {
  btRigidBody* free = find_free_body(impl, body);
  if (!free) throw Error("physics: body " + std::to_string(body) + " is not a free body");
  return free;
}

}  // namespace

bool PhysicsWorld::is_free_body(int body) const { return find_free_body(*impl_, body) != nullptr; }

FreeBodyState PhysicsWorld::free_body_state(int body) const {
  const btRigidBody* free = free_body_of(*impl_, body);
  const btTransform& t = free->getWorldTransform();
  FreeBodyState s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s.transform[3 * r + c] = static_cast<float>(t.getBasis()[r][c]);
  for (int i = 0; i < 3; ++i) s.transform[9 + i] = static_cast<float>(t.getOrigin()[i]);
  s.linear = from_bt(free->getLinearVelocity());
  s.angular = from_bt(free->getAngularVelocity());
  return s;
}

void PhysicsWorld::set_free_body_friction(int body, float friction) {
  btRigidBody* free = free_body_of(*impl_, body);
  if (!(friction >= 0.0f) || !std::isfinite(friction))
    throw Error("physics: friction must be a finite number >= 0, got " + std::to_string(friction));
  free->setFriction(friction);
  free->setCollisionFlags(free->getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
}

float PhysicsWorld::free_body_friction(int body) const { return free_body_of(*impl_, body)->getFriction(); }

void PhysicsWorld::set_free_body_mass_scale(int body, double scale) {
  btRigidBody* free = free_body_of(*impl_, body);
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw Error("physics: a mass scale must be a finite number > 0, got " + std::to_string(scale));
  const Eigen::Vector4d nominal = impl_->free_masses[static_cast<size_t>(body)] * scale;
  free->setMassProps(static_cast<btScalar>(nominal[0]), to_bt(Eigen::Vector3d(nominal.tail<3>())));
  free->updateInertiaTensor();
}

double PhysicsWorld::free_body_mass(int body) const { return 1.0 / free_body_of(*impl_, body)->getInvMass(); }

void PhysicsWorld::set_free_body_state(int body, const FreeBodyState& state) {
  btRigidBody* free = free_body_of(*impl_, body);
  const float* m = state.transform;
  const btTransform t(btMatrix3x3(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8]), btVector3(m[9], m[10], m[11]));
  // Velocities first: setCenterOfMassTransform copies them as the interpolation velocities, as a
  // step's integration does, and turns the world inertia with the frame.
  free->setLinearVelocity(to_bt(state.linear));
  free->setAngularVelocity(to_bt(state.angular));
  free->setCenterOfMassTransform(t);
  free->clearForces();
  if (free->getBroadphaseHandle()) {
    impl_->world.updateSingleAabb(free);
    impl_->forget_pairs(free);
  }
}

Robot& PhysicsWorld::add_robot(const RobotModel& model, const Eigen::Isometry3f& base_pose,
                               const RobotOptions& options) {
  const int body = body_count();
  impl_->robots.push_back(std::make_unique<Robot>(*this, body, model, base_pose, options));
  impl_->statics.push_back(nullptr);
  impl_->static_offsets.push_back(Eigen::Isometry3f::Identity());
  return *impl_->robots.back();
}

Robot& PhysicsWorld::robot(int body) {
  return const_cast<Robot&>(static_cast<const PhysicsWorld*>(this)->robot(body));
}

const Robot& PhysicsWorld::robot(int body) const {
  if (body < 0 || body >= body_count() || !impl_->robots[static_cast<size_t>(body)])
    throw Error("physics: body " + std::to_string(body) + " is not a robot");
  return *impl_->robots[static_cast<size_t>(body)];
}

int PhysicsWorld::body_count() const { return static_cast<int>(impl_->robots.size()); }

void PhysicsWorld::step() {
  for (auto& r : impl_->robots)
    if (r) r->before_step();
  const auto dt = static_cast<btScalar>(settings_.time_step);
  impl_->world.stepSimulation(dt, 0, dt);  // maxSubSteps = 0: exactly one step of dt
  time_ += settings_.time_step;
  ++steps_;
}

PhysicsWorld::Work PhysicsWorld::work() const {
  return Work{steps_, impl_->solver.iterations(), impl_->dispatcher.skipped};
}

std::vector<Contact> PhysicsWorld::contacts(float max_distance) const {
  std::vector<Contact> out;
  const int n = impl_->dispatcher.getNumManifolds();
  for (int i = 0; i < n; ++i) {
    const btPersistentManifold* m = impl_->dispatcher.getManifoldByIndexInternal(i);
    for (int k = 0; k < m->getNumContacts(); ++k) {
      const btManifoldPoint& p = m->getContactPoint(k);
      if (p.getDistance() > max_distance) continue;
      out.push_back(Contact{body_link(m->getBody0()), body_link(m->getBody1()), from_bt(p.getPositionWorldOnA()),
                            from_bt(p.getPositionWorldOnB()), from_bt(p.m_normalWorldOnB), p.getDistance()});
    }
  }
  return out;
}

bool PhysicsWorld::touching(BodyLink a, BodyLink b, float tolerance) const {
  bool found = false;
  for_each_point(impl_->dispatcher, a, b, [&](const btManifoldPoint& p) { found |= p.getDistance() < tolerance; });
  return found;
}

float PhysicsWorld::penetration(BodyLink a, BodyLink b) const {
  float deepest = 0.0f;
  for_each_point(impl_->dispatcher, a, b, [&](const btManifoldPoint& p) { deepest = std::max(deepest, -p.getDistance()); });
  return deepest;
}

void PhysicsWorld::forget_contacts(int body) {
  if (body < 0 || body >= body_count()) throw Error("physics: no body " + std::to_string(body));
  if (auto& s = impl_->statics[static_cast<size_t>(body)]) {
    impl_->forget_pairs(s.get());
    return;
  }
  btCollisionObjectArray& objects = impl_->world.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i)
    if (objects[i]->getUserIndex() == body) impl_->forget_pairs(objects[i]);
}

void PhysicsWorld::forget_all_contacts() {
  btCollisionObjectArray& objects = impl_->world.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) impl_->forget_pairs(objects[i]);
  impl_->solver.forget_warm_starts();
}

}  // namespace rdsim
