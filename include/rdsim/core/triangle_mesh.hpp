#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

// A triangle mesh as plain data, shared (read-only, through shared_ptr<const TriangleMesh>) by the
// robot model that loaded it, the physics that collides with it and the renderers that draw it.
// It lives in core because those three libraries see core and not each other.
namespace rdsim {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> positions;  // metres, in the frame of the URDF element (scale applied)
  std::vector<Eigen::Vector3f> normals;    // unit length, one per position
  // Diffuse colours from the file's own materials (OBJ .mtl, DAE effects), one per position in
  // [0, 1]; empty when the file has none. A renderer multiplies them with the element's colour.
  std::vector<Eigen::Vector3f> colors;
  // Three per triangle, counter-clockwise seen from outside (as the file winds them).
  std::vector<std::uint32_t> indices;

  std::size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace rdsim
