#pragma once
// Low-poly unit shapes generated once; an item is its unit mesh under a scaled model matrix.
// Meshes are indexed so that each shared vertex is transformed and lit once per frame.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace rdsim::render {

// Box [-1,1]^3; Cylinder radius 1, z in [-1,1]; Sphere radius 1; Hemisphere the z >= 0 half of
// the sphere, open at z = 0 (capsule caps); Quad [-1,1]^2 at z = 0 facing +z.
enum class UnitMesh { Box, Cylinder, Sphere, Hemisphere, Quad };
constexpr int kUnitMeshCount = 5;

struct MeshRange {
  int first_vertex = 0, vertex_count = 0;
  int first_index = 0, index_count = 0;  // three per triangle
};

struct UnitMeshes {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // unit length, one per position
  // Triangles, counter-clockwise seen from outside so back faces can be culled. Indices count
  // from their mesh's first_vertex.
  std::vector<std::uint16_t> indices;
  std::array<MeshRange, kUnitMeshCount> ranges{};

  const MeshRange& range(UnitMesh m) const { return ranges[static_cast<int>(m)]; }
};

constexpr int kCylinderSegments = 16;
constexpr int kSphereStacks = 8;  // the hemisphere uses half of them
constexpr int kSphereSlices = 12;

UnitMeshes build_unit_meshes();

}  // namespace rdsim::render
