#pragma once
// Bullet objects behind PhysicsWorld and Robot; only src/sim includes this.
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

#include "rdsim/sim/physics_world.hpp"
#include "filtered_broadphase.hpp"
#include "separated_pairs.hpp"
#include "sparse_row_solver.hpp"

namespace rdsim {

// Collision filter groups (see physics_world.hpp for the rules).
constexpr int kStaticGroup = btBroadphaseProxy::StaticFilter;
constexpr int kRobotLinkGroup = 1 << 6;  // moving links
constexpr int kRobotBaseGroup = 1 << 7;  // a fixed base and links welded to it
constexpr int kFreeBodyGroup = btBroadphaseProxy::DefaultFilter;  // add_free_body
constexpr int kStaticMask = kRobotLinkGroup | btBroadphaseProxy::DefaultFilter;
constexpr int kRobotLinkMask = kStaticGroup | btBroadphaseProxy::DefaultFilter;
constexpr int kRobotBaseMask = btBroadphaseProxy::DefaultFilter;

inline btVector3 to_bt(const Eigen::Vector3f& v) { return btVector3(v.x(), v.y(), v.z()); }
inline btVector3 to_bt(const Eigen::Vector3d& v) {
  return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()), static_cast<btScalar>(v.z()));
}
inline Eigen::Vector3f from_bt(const btVector3& v) { return Eigen::Vector3f(v.x(), v.y(), v.z()); }
btTransform to_bt(const Eigen::Isometry3f& t);
btTransform to_bt(const Eigen::Isometry3d& t);
Eigen::Isometry3f from_bt(const btTransform& t);

// The placed shapes of one body as one Bullet shape: the shape itself when there is a single
// shape at the body's origin, else a compound. Shapes are owned by `store`. Meshes become
// triangle meshes on a static body, convex hulls otherwise (src/sim/collision_shapes.cpp).
struct PlacedShape {
  Shape shape;
  Eigen::Isometry3d pose;  // in the body's frame
};
btCollisionShape* make_collision_shape(const std::vector<PlacedShape>& shapes, bool static_body,
                                       std::vector<std::unique_ptr<btCollisionShape>>& store);

// Bullet's multibody world minus one pass we never use: predicting where each link will be at the
// end of the step only feeds continuous collision detection, which rdsim does not enable.
class MultiBodyWorld : public btMultiBodyDynamicsWorld {
public:
  using btMultiBodyDynamicsWorld::btMultiBodyDynamicsWorld;
  void predictUnconstraintMotion(btScalar time_step) override {
    btDiscreteDynamicsWorld::predictUnconstraintMotion(time_step);  // rigid bodies only
  }
};

struct PhysicsWorld::Impl {
  btDefaultCollisionConfiguration config;
  PairDispatcher dispatcher{&config};
  FilteredBroadphase broadphase;
  SparseRowSolver solver;
  MultiBodyWorld world{&dispatcher, &broadphase, &solver, &config};

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  // Per body id: its static collision object, or null for a robot.
  std::vector<std::unique_ptr<btCollisionObject>> statics;
  // Per body id: where a static body's single shape sits in the body (its object carries it).
  std::vector<Eigen::Isometry3f> static_offsets;
  std::vector<std::unique_ptr<Robot>> robots;  // per body id; null for a static body
  // Per body id: a free body's mass (kg) and principal moments (kg m^2) as its model gives them
  // (PhysicsWorld::set_free_body_mass_scale scales these); zero for other bodies.
  std::vector<Eigen::Vector4d> free_masses;

  ~Impl();
  // Removes every cached pair (and contact manifold) involving this object.
  void forget_pairs(btCollisionObject* object);
};

}  // namespace rdsim
