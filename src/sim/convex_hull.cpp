// Convex hulls of collision meshes (rdsim/sim/mesh_file.hpp).
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btShapeHull.h>
#include <LinearMath/btConvexHullComputer.h>

#include <vector>

#include "rdsim/sim/mesh_file.hpp"

namespace rdsim {
namespace {

// The exact hull of `points`: its vertices, and its volume from a fan of tetrahedra per face.
ConvexHull exact_hull(const std::vector<Eigen::Vector3f>& points) {
  btConvexHullComputer computer;
  computer.compute(&points[0].x(), static_cast<int>(sizeof(Eigen::Vector3f)), static_cast<int>(points.size()), 0, 0);
  ConvexHull hull;
  for (int i = 0; i < computer.vertices.size(); ++i) {
    const btVector3& v = computer.vertices[i];
    hull.points.emplace_back(v.x(), v.y(), v.z());
  }
  if (hull.points.empty()) return hull;
  const Eigen::Vector3d apex = hull.points[0].cast<double>();
  double six_volume = 0.0;
  for (int f = 0; f < computer.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &computer.edges[computer.faces[f]];
    const Eigen::Vector3d a = hull.points[static_cast<std::size_t>(first->getSourceVertex())].cast<double>() - apex;
    const btConvexHullComputer::Edge* e = first->getNextEdgeOfFace();
    for (const btConvexHullComputer::Edge* next = e->getNextEdgeOfFace(); next != first; e = next, next = next->getNextEdgeOfFace()) {
      const Eigen::Vector3d b = hull.points[static_cast<std::size_t>(e->getSourceVertex())].cast<double>() - apex;
      const Eigen::Vector3d c = hull.points[static_cast<std::size_t>(next->getSourceVertex())].cast<double>() - apex;
      six_volume += a.dot(b.cross(c));
    }
  }
  hull.volume = std::abs(six_volume) / 6.0;
  return hull;
}

}  // namespace

ConvexHull convex_hull(const TriangleMesh& mesh) {
  if (mesh.positions.empty()) return {};
  ConvexHull hull = exact_hull(mesh.positions);
  if (hull.points.size() <= max_hull_points) return hull;
  // Too many vertices for a cheap support function: keep the hull's support points in btShapeHull's
  // fixed set of directions, then the exact hull of those.
  btConvexHullShape full;
  for (const Eigen::Vector3f& p : hull.points) full.addPoint(btVector3(p.x(), p.y(), p.z()), false);
  full.recalcLocalAabb();
  full.setMargin(0.0f);
  btShapeHull reducer(&full);
  reducer.buildHull(0.0f);
  std::vector<Eigen::Vector3f> reduced;
  for (int i = 0; i < reducer.numVertices(); ++i) {
    const btVector3& v = reducer.getVertexPointer()[i];
    reduced.emplace_back(v.x(), v.y(), v.z());
  }
  return exact_hull(reduced);
}

}  // namespace rdsim
