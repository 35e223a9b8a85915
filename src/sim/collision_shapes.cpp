// Bullet collision shapes from rdsim Shapes.
//
// Meshes, as Bullet users expect: a link of a robot collides through the convex hull of its mesh
// (btConvexHullShape over the hull's at most max_hull_points vertices, computed once per file and
// scale); a static body collides with the mesh's triangles themselves (btBvhTriangleMeshShape,
// concave allowed, built per world). Both take a 1 mm margin (pybullet's default for URDF meshes):
// Bullet adds it outside a hull, and the default 4 cm would make parts collide early.
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>

#include <algorithm>

#include "physics_world_impl.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

// Box and cylinder margins sit inside the shape in Bullet, so they only round its edges. The
// default (4 cm) would swallow our small parts; 4 mm keeps edges nearly sharp while leaving GJK
// its margin, and never more than a quarter of the thinnest half-extent.
btScalar margin_for(const btVector3& half_extents) {
  return std::min(btScalar(0.004), btScalar(0.25) * half_extents[half_extents.minAxis()]);
}

constexpr btScalar kMeshMargin = 0.001f;  // m

std::unique_ptr<btCollisionShape> make_hull(const ConvexHull& hull) {
  auto shape = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector3f& p : hull.points) shape->addPoint(to_bt(p), false);
  shape->recalcLocalAabb();
  shape->setMargin(kMeshMargin);
  return shape;
}

// A triangle-mesh shape that owns its index/vertex view (the mesh data itself is shared, immutable).
class OwningTriangleMeshShape : public btBvhTriangleMeshShape {
public:
  OwningTriangleMeshShape(std::unique_ptr<btTriangleIndexVertexArray> triangles, std::shared_ptr<const TriangleMesh> mesh)
      : btBvhTriangleMeshShape(triangles.get(), true), triangles_(std::move(triangles)), mesh_(std::move(mesh)) {}

private:
  std::unique_ptr<btTriangleIndexVertexArray> triangles_;
  std::shared_ptr<const TriangleMesh> mesh_;
};

std::unique_ptr<btCollisionShape> make_triangle_mesh(const std::shared_ptr<const TriangleMesh>& mesh) {
  btIndexedMesh part;
  part.m_numTriangles = static_cast<int>(mesh->triangle_count());
  part.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(mesh->indices.data());
  part.m_triangleIndexStride = 3 * sizeof(std::uint32_t);
  part.m_numVertices = static_cast<int>(mesh->positions.size());
  part.m_vertexBase = reinterpret_cast<const unsigned char*>(mesh->positions.data());
  part.m_vertexStride = sizeof(Eigen::Vector3f);
  part.m_indexType = PHY_INTEGER;
  part.m_vertexType = PHY_FLOAT;
  auto triangles = std::make_unique<btTriangleIndexVertexArray>();
  triangles->addIndexedMesh(part, PHY_INTEGER);
  auto shape = std::make_unique<OwningTriangleMeshShape>(std::move(triangles), mesh);
  shape->setMargin(kMeshMargin);
  return shape;
}

std::unique_ptr<btCollisionShape> make_primitive(const Shape& s, bool static_body) {
  switch (s.type) {
    case ShapeType::Box: {
      const btVector3 half = to_bt(s.size) * btScalar(0.5);
      auto box = std::make_unique<btBoxShape>(half);
      box->setMargin(margin_for(half));
      return box;
    }
    case ShapeType::Cylinder: {
      const btVector3 half(static_cast<btScalar>(s.radius), static_cast<btScalar>(s.radius),
                           static_cast<btScalar>(s.length * 0.5));
      auto cylinder = std::make_unique<btCylinderShapeZ>(half);
      cylinder->setMargin(margin_for(half));
      return cylinder;
    }
    case ShapeType::Sphere:
      return std::make_unique<btSphereShape>(static_cast<btScalar>(s.radius));
    case ShapeType::Mesh:
      if (static_body) return make_triangle_mesh(s.mesh.mesh);
      if (!s.mesh.hull) throw Error("physics: mesh \"" + s.mesh.uri + "\" has no convex hull (not a <collision> element)");
      return make_hull(*s.mesh.hull);
  }
  return nullptr;
}

bool is_identity(const Eigen::Isometry3d& t) { return t.matrix().isIdentity(1e-9); }

}  // namespace

btTransform to_bt(const Eigen::Isometry3f& t) {
  const Eigen::Matrix3f& r = t.linear();
  return btTransform(btMatrix3x3(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)),
                     to_bt(Eigen::Vector3f(t.translation())));
}

btTransform to_bt(const Eigen::Isometry3d& t) { return to_bt(Eigen::Isometry3f(t.cast<float>())); }

Eigen::Isometry3f from_bt(const btTransform& t) {
  Eigen::Isometry3f out = Eigen::Isometry3f::Identity();
  const btMatrix3x3& r = t.getBasis();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.linear()(i, j) = r[i][j];
  out.translation() = from_bt(t.getOrigin());
  return out;
}

btCollisionShape* make_collision_shape(const std::vector<PlacedShape>& shapes, bool static_body,
                                       std::vector<std::unique_ptr<btCollisionShape>>& store) {
  if (shapes.empty()) return nullptr;
  if (shapes.size() == 1 && is_identity(shapes[0].pose)) {
    store.push_back(make_primitive(shapes[0].shape, static_body));
    return store.back().get();
  }
  // A handful of children: a flat list is cheaper than the compound's AABB tree.
  auto compound = std::make_unique<btCompoundShape>(shapes.size() > 8);
  for (const auto& p : shapes) {
    store.push_back(make_primitive(p.shape, static_body));
    compound->addChildShape(to_bt(p.pose), store.back().get());
  }
  store.push_back(std::move(compound));
  return store.back().get();
}

}  // namespace rdsim
