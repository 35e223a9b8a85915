#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "rdsim/core/triangle_mesh.hpp"

namespace rdsim {

// Primitive kinds the renderer draws. Every shape is centred on its pose's origin.
// (DrawShape, not Shape: rdsim::Shape is the URDF geometry of robot_model.hpp, and envs include both.)
enum class DrawShape { Box, Cylinder, Sphere, Capsule, Plane, Mesh };

// One drawable primitive. Meaning of `size` per kind (MuJoCo/Bullet conventions):
//   Box:      size = half extents (x, y, z)
//   Cylinder: size.x = radius, size.y = full length along local z
//   Sphere:   size.x = radius
//   Capsule:  size.x = radius, size.y = distance between the two cap centres, along local z
//             (the cylindrical part; total length is size.y + 2 * size.x)
//   Plane:    local xy plane facing +z, size.x/size.y = half extents; 0 means "as far as the
//             camera sees" (zfar). Seen from below (-z side) it is not drawn.
//   Mesh:     `mesh`'s triangles as they are (size unused); its own colours, when it has any,
//             are multiplied with rgb. Triangles seen from behind are not drawn.
// rgba: colours in [0, 1]. Items are opaque; alpha == 0 hides the item without removing it.
// segment: the id a segmentation image shows where the item is visible (RenderTargets); 0 is
// the background's, so an item left at 0 is indistinguishable from it.
struct DrawItem {
  DrawShape kind = DrawShape::Box;
  Eigen::Vector3f size{0.05f, 0.05f, 0.05f};
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  Eigen::Vector4f rgba{0.7f, 0.7f, 0.7f, 1.0f};
  std::shared_ptr<const TriangleMesh> mesh;  // Mesh only; shared, never changed
  std::uint8_t segment = 0;
};

DrawItem make_box(const Eigen::Vector3f& half_extents, const Eigen::Vector4f& rgba);
DrawItem make_cylinder(float radius, float length, const Eigen::Vector4f& rgba);
DrawItem make_sphere(float radius, const Eigen::Vector4f& rgba);
DrawItem make_capsule(float radius, float length, const Eigen::Vector4f& rgba);
DrawItem make_plane(float half_x, float half_y, const Eigen::Vector4f& rgba);
DrawItem make_mesh(std::shared_ptr<const TriangleMesh> mesh, const Eigen::Vector4f& rgba);

// What to draw. The env builds the item list once (one item per visual shape) and then only
// writes poses each frame, so an update costs one Isometry3f copy per item.
struct Scene {
  std::vector<DrawItem> items;
  Eigen::Vector3f background{0.8f, 0.8f, 0.8f};         // clear colour, light grey
  Eigen::Vector3f light_direction{-0.4f, -0.3f, -1.0f};  // world direction the light travels
  float ambient = 0.35f;                                 // light intensities, per channel
  float diffuse = 0.65f;

  // Appends an item and returns its index for later set_pose calls.
  int add(const DrawItem& item);
  // std::out_of_range when index is not an item of this scene.
  void set_pose(int index, const Eigen::Isometry3f& pose);
};

}  // namespace rdsim
