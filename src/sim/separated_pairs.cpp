#include "separated_pairs.hpp"

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace rdsim {
namespace {

// 1 mm: room for GJK's own tolerance on top of the manifold's threshold.
constexpr btScalar kSafety = btScalar(1e-3);

// True when `other` (convex) lies, along one of the box's axes, more than `gap` (m) beyond the box.
bool separated(const btCollisionObject& box_object, const btBoxShape& box, const btCollisionObject& other, btScalar gap) {
  const auto& convex = static_cast<const btConvexShape&>(*other.getCollisionShape());
  const btTransform& box_pose = box_object.getWorldTransform();
  const btTransform& pose = other.getWorldTransform();
  const btVector3 half = box.getHalfExtentsWithMargin();
  for (int k = 0; k < 3; ++k) {
    const btVector3 axis = box_pose.getBasis().getColumn(k);
    const btVector3 local = axis * pose.getBasis();  // the axis in the other shape's frame
    const btScalar centre = axis.dot(box_pose.getOrigin());
    const btScalar highest = axis.dot(pose(convex.localGetSupportingVertex(local)));
    const btScalar lowest = axis.dot(pose(convex.localGetSupportingVertex(-local)));
    if (lowest - (centre + half[k]) > gap || (centre - half[k]) - highest > gap) return true;
  }
  return false;
}

bool skippable(const btBroadphasePair& pair) {
  if (!pair.m_algorithm) return false;
  thread_local btManifoldArray manifolds;
  manifolds.resize(0);
  pair.m_algorithm->getAllContactManifolds(manifolds);
  if (manifolds.size() != 1 || manifolds[0]->getNumContacts() != 0) return false;
  const auto* a = static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject);
  const auto* b = static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject);
  if (a->getCollisionShape()->getShapeType() != BOX_SHAPE_PROXYTYPE) std::swap(a, b);
  if (a->getCollisionShape()->getShapeType() != BOX_SHAPE_PROXYTYPE || !b->getCollisionShape()->isConvex()) return false;
  const btScalar gap = manifolds[0]->getContactBreakingThreshold() + kSafety;
  return separated(*a, static_cast<const btBoxShape&>(*a->getCollisionShape()), *b, gap);
}

}  // namespace

void skip_separated_pairs(btBroadphasePair& pair, btCollisionDispatcher& dispatcher, const btDispatcherInfo& info) {
  if (skippable(pair)) {
    ++static_cast<PairDispatcher&>(dispatcher).skipped;
    return;
  }
  btCollisionDispatcher::defaultNearCallback(pair, dispatcher, info);
}

}  // namespace rdsim
