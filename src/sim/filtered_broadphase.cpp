#include "filtered_broadphase.hpp"

namespace rdsim {

void FilteredBroadphase::calculateOverlappingPairs(btDispatcher* dispatcher) {
  // Bullet's pass with a pair cache that removes pairs as it goes (rdsim's), else Bullet's own.
  if (!filter_first_ || m_numHandles < 0 || m_pairCache->hasDeferredRemoval()) {
    btSimpleBroadphase::calculateOverlappingPairs(dispatcher);
    return;
  }
  int last_used = -1;
  for (int i = 0; i <= m_LastHandleIndex; ++i) {
    btSimpleBroadphaseProxy* a = &m_pHandles[i];
    if (!a->m_clientObject) continue;
    last_used = i;
    for (int j = i + 1; j <= m_LastHandleIndex; ++j) {
      btSimpleBroadphaseProxy* b = &m_pHandles[j];
      if (!b->m_clientObject || !m_pairCache->needsBroadphaseCollision(a, b)) continue;
      if (aabbOverlap(a, b)) {
        if (!m_pairCache->findPair(a, b)) m_pairCache->addOverlappingPair(a, b);
      } else if (m_pairCache->findPair(a, b)) {
        m_pairCache->removeOverlappingPair(a, b, dispatcher);
      }
    }
  }
  m_LastHandleIndex = last_used;
}

}  // namespace rdsim
