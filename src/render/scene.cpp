#include "rdsim/render/scene.hpp"

#include <stdexcept>
#include <string>
#include <utility>

namespace rdsim {
namespace {
DrawItem make_item(DrawShape kind, const Eigen::Vector3f& size, const Eigen::Vector4f& rgba) {
  DrawItem item;
  item.kind = kind;
  item.size = size;
  item.rgba = rgba;
  return item;
}
}  // namespace

DrawItem make_box(const Eigen::Vector3f& half_extents, const Eigen::Vector4f& rgba) {
  return make_item(DrawShape::Box, half_extents, rgba);
}

DrawItem make_cylinder(float radius, float length, const Eigen::Vector4f& rgba) {
  return make_item(DrawShape::Cylinder, {radius, length, 0.0f}, rgba);
}

DrawItem make_sphere(float radius, const Eigen::Vector4f& rgba) {
  return make_item(DrawShape::Sphere, {radius, 0.0f, 0.0f}, rgba);
}

DrawItem make_capsule(float radius, float length, const Eigen::Vector4f& rgba) {
  return make_item(DrawShape::Capsule, {radius, length, 0.0f}, rgba);
}

DrawItem make_plane(float half_x, float half_y, const Eigen::Vector4f& rgba) {
  return make_item(DrawShape::Plane, {half_x, half_y, 0.0f}, rgba);
}

DrawItem make_mesh(std::shared_ptr<const TriangleMesh> mesh, const Eigen::Vector4f& rgba) {
  DrawItem item = make_item(DrawShape::Mesh, Eigen::Vector3f::Ones(), rgba);
  item.mesh = std::move(mesh);
  return item;
}

int Scene::add(const DrawItem& item) {
  items.push_back(item);
  return static_cast<int>(items.size()) - 1;
}

void Scene::set_pose(int index, const Eigen::Isometry3f& pose) {
  if (index < 0 || index >= static_cast<int>(items.size()))
    throw std::out_of_range("Scene::set_pose: no item " + std::to_string(index) + " (scene has " +
                            std::to_string(items.size()) + ")");
  items[static_cast<size_t>(index)].pose = pose;
}

}  // namespace rdsim
