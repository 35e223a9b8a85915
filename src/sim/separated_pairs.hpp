#pragma once
// A near callback for Bullet's dispatcher that skips the narrow phase of a pair which is provably
// too far apart to touch; only src/sim includes this.
//
// Why: a robot reaching down to a table keeps several links' bounding boxes overlapping the
// floor's and the button's (Bullet's broadphase pads them by the contact margin), and Bullet runs
// GJK on every such pair every step, though almost all of them are centimetres apart and yield no
// contact point. That was most of the JAKA paper preset's collision detection.
//
// Exact: a pair is skipped only when (1) Bullet already holds its collision algorithm with one
// contact manifold and that manifold has no points (so there is nothing to refresh or drop, and
// skipping creates or destroys nothing: the manifolds keep Bullet's order), (2) one side is a box
// and the other a convex shape, and (3) along one of the box's axes the convex shape's support
// points (margins included) lie farther from the box's face than the manifold's contact-breaking
// threshold plus 1 mm: GJK would find the shapes at least that far apart and add no point.
// tests/sim compares whole simulations with and without it, bit for bit.
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>

namespace rdsim {

// Bullet's dispatcher, counting the pairs skip_separated_pairs skips.
class PairDispatcher : public btCollisionDispatcher {
public:
  using btCollisionDispatcher::btCollisionDispatcher;
  long long skipped = 0;
};

// The near callback of a PairDispatcher: Bullet's own, unless the pair is provably apart.
void skip_separated_pairs(btBroadphasePair& pair, btCollisionDispatcher& dispatcher, const btDispatcherInfo& info);

}  // namespace rdsim
