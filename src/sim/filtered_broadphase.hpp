#pragma once
// Bullet's simple broadphase, without the pair-cache lookups for pairs the collision filter rules
// out; only src/sim includes this.
//
// Why: btSimpleBroadphase tests every pair of objects every step, and for each one it looks the
// pair up in the pair cache (to add it when their boxes overlap, to remove it when they do not).
// In a robot scene most pairs can never collide (a robot's links with each other, static bodies
// with each other, the fixed base with the statics), and the cache refuses them: the lookups
// find nothing and change nothing. With eleven objects that was 55 lookups a step for about 20
// pairs that matter.
//
// Exact: the same pairs are added and removed in the same order. A pair the filter rules out is
// never in the cache (its addOverlappingPair refuses it, and rdsim adds pairs no other way), so
// Bullet's lookups of it would find nothing; every other pair goes through Bullet's steps.
// tests/sim compares whole simulations with it and Bullet's own broadphase, bit for bit.
#include <BulletCollision/BroadphaseCollision/btSimpleBroadphase.h>

namespace rdsim {

class FilteredBroadphase : public btSimpleBroadphase {
public:
  // false: Bullet's own pass (for the tests that show the two agree).
  void set_filter_first(bool on) { filter_first_ = on; }
  void calculateOverlappingPairs(btDispatcher* dispatcher) override;

private:
  bool filter_first_ = true;
};

}  // namespace rdsim
