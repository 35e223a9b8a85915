#include "gl_scene_drawer.hpp"

#include <algorithm>
#include <cstddef>

#include "rdsim/core/error.hpp"

namespace rdsim::render {
namespace {

Eigen::Matrix4f scaled(const Eigen::Matrix4f& m, const Eigen::Vector3f& s) {
  Eigen::Matrix4f out = m;
  out.col(0) *= s.x();
  out.col(1) *= s.y();
  out.col(2) *= s.z();
  return out;
}

Eigen::Matrix4f translated_z(const Eigen::Matrix4f& m, float z) {
  Eigen::Matrix4f out = m;
  out.col(3) += z * m.col(2);
  return out;
}

std::uint8_t to_byte(float v) {
  return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
}

// Swaps rows in place: GL reads bottom-up, our images are top-down.
void flip_rows(std::uint8_t* rgb, int width, int height) {
  const size_t row = static_cast<size_t>(width) * 3;
  for (int top = 0, bottom = height - 1; top < bottom; ++top, --bottom)
    std::swap_ranges(rgb + row * static_cast<size_t>(top), rgb + row * static_cast<size_t>(top + 1),
                     rgb + row * static_cast<size_t>(bottom));
}

// Metres along the view direction from a depth-buffer value d in [0, 1] of a perspective
// projection with clip planes n and f: the inverse of d = (f / (f - n)) (1 - n / z). In double:
// near f the float form loses the millimetres.
float linear_depth(float d, double n, double f) { return static_cast<float>(n * f / (f - static_cast<double>(d) * (f - n))); }

}  // namespace

GlSceneDrawer::GlSceneDrawer(const GlApi& gl, int width, int height)
    : gl_(gl), width_(width), height_(height), meshes_(build_unit_meshes()) {
  gl_.glViewport(0, 0, width_, height_);
  gl_.glEnable(GL_DEPTH_TEST);
  gl_.glEnable(GL_CULL_FACE);
  gl_.glCullFace(GL_BACK);
  gl_.glFrontFace(GL_CCW);
  gl_.glDisable(GL_LIGHTING);
  gl_.glShadeModel(GL_SMOOTH);
  gl_.glEnableClientState(GL_VERTEX_ARRAY);
  gl_.glEnableClientState(GL_COLOR_ARRAY);
  const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
  gl_.glMatrixMode(GL_MODELVIEW);
  gl_.glLoadMatrixf(identity.data());
  gl_.glMatrixMode(GL_PROJECTION);
  gl_.glPixelStorei(GL_PACK_ALIGNMENT, 1);
  if (gl_.glGetError() != GL_NO_ERROR) throw Error("renderer: GL setup failed");
}

void GlSceneDrawer::add_mesh(UnitMesh mesh, const Eigen::Matrix4f& model_view, const Paint& paint,
                             const Lighting& light) {
  const Eigen::Vector3f& rgb = paint.rgb;
  const MeshRange& r = meshes_.range(mesh);
  const Eigen::Matrix3f linear = model_view.topLeftCorner<3, 3>();
  const Eigen::Vector3f offset = model_view.topRightCorner<3, 1>();
  // Normals transform by the inverse transpose, which undoes non-uniform scale.
  const Eigen::Matrix3f normal_matrix = linear.inverse().transpose();
  const auto base = static_cast<GLuint>(vertices_.size());
  for (int i = r.first_vertex; i < r.first_vertex + r.vertex_count; ++i) {
    const Eigen::Vector3f p = linear * meshes_.positions[static_cast<size_t>(i)] + offset;
    const Eigen::Vector3f n = (normal_matrix * meshes_.normals[static_cast<size_t>(i)]).normalized();
    const float shade = light.ambient + light.diffuse * std::max(0.0f, n.dot(light.to_light));
    vertices_.push_back({p.x(), p.y(), p.z(),
                         {to_byte(rgb.x() * shade), to_byte(rgb.y() * shade),
                          to_byte(rgb.z() * shade), paint.segment}});
  }
  const std::uint16_t* tri = meshes_.indices.data() + r.first_index;
  for (int t = 0; t < r.index_count; t += 3, tri += 3) add_if_facing(base + tri[0], base + tri[1], base + tri[2]);
}

void GlSceneDrawer::add_triangle_mesh(const TriangleMesh& mesh, const Eigen::Matrix4f& model_view,
                                      const Paint& paint, const Lighting& light) {
  const Eigen::Vector3f& rgb = paint.rgb;
  const Eigen::Matrix3f linear = model_view.topLeftCorner<3, 3>();
  const Eigen::Vector3f offset = model_view.topRightCorner<3, 1>();
  const auto base = static_cast<GLuint>(vertices_.size());
  const bool coloured = mesh.colors.size() == mesh.positions.size();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3f p = linear * mesh.positions[i] + offset;
    const Eigen::Vector3f n = linear * mesh.normals[i];  // a rigid pose: no inverse transpose needed
    const float shade = light.ambient + light.diffuse * std::max(0.0f, n.dot(light.to_light));
    const Eigen::Vector3f c = coloured ? Eigen::Vector3f(rgb.cwiseProduct(mesh.colors[i])) : rgb;
    vertices_.push_back({p.x(), p.y(), p.z(),
                         {to_byte(c.x() * shade), to_byte(c.y() * shade), to_byte(c.z() * shade), paint.segment}});
  }
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
    add_if_facing(base + mesh.indices[t], base + mesh.indices[t + 1], base + mesh.indices[t + 2]);
}

// Back faces culled here rather than by GL: half the triangles then skip the rasteriser's
// per-triangle clip and setup work. In eye space the camera sits at the origin, so a triangle
// faces it when its (counter-clockwise) normal points back towards the origin.
void GlSceneDrawer::add_if_facing(GLuint ia, GLuint ib, GLuint ic) {
  const Vertex& a = vertices_[ia];
  const Vertex& b = vertices_[ib];
  const Vertex& c = vertices_[ic];
  const Eigen::Vector3f pa(a.x, a.y, a.z);
  const Eigen::Vector3f normal = (Eigen::Vector3f(b.x, b.y, b.z) - pa).cross(Eigen::Vector3f(c.x, c.y, c.z) - pa);
  if (normal.dot(pa) < 0.0f) indices_.insert(indices_.end(), {ia, ib, ic});
}

void GlSceneDrawer::add_item(const DrawItem& item, const Eigen::Matrix4f& view, float far_extent,
                             const Lighting& light) {
  const Eigen::Matrix4f mv = view * item.pose.matrix();
  const Eigen::Vector3f& s = item.size;
  const Paint paint{item.rgba.head<3>(), item.segment};
  switch (item.kind) {
    case DrawShape::Box:
      add_mesh(UnitMesh::Box, scaled(mv, s), paint, light);
      break;
    case DrawShape::Cylinder:
      add_mesh(UnitMesh::Cylinder, scaled(mv, {s.x(), s.x(), 0.5f * s.y()}), paint, light);
      break;
    case DrawShape::Sphere:
      add_mesh(UnitMesh::Sphere, scaled(mv, Eigen::Vector3f::Constant(s.x())), paint, light);
      break;
    case DrawShape::Capsule: {
      const float r = s.x(), half = 0.5f * s.y();
      if (half > 0.0f) add_mesh(UnitMesh::Cylinder, scaled(mv, {r, r, half}), paint, light);
      // The lower cap is the upper one turned upside down (x and z flipped: a rotation).
      add_mesh(UnitMesh::Hemisphere, scaled(translated_z(mv, half), Eigen::Vector3f::Constant(r)),
               paint, light);
      add_mesh(UnitMesh::Hemisphere, scaled(translated_z(mv, -half), {-r, r, -r}), paint, light);
      break;
    }
    case DrawShape::Mesh:
      if (item.mesh) add_triangle_mesh(*item.mesh, mv, paint, light);
      break;
    case DrawShape::Plane: {
      const float hx = s.x() > 0.0f ? s.x() : far_extent;
      const float hy = s.y() > 0.0f ? s.y() : far_extent;
      add_mesh(UnitMesh::Quad, scaled(mv, {hx, hy, 1.0f}), paint, light);
      break;
    }
  }
}

void GlSceneDrawer::draw(const Scene& scene, const Camera& camera, const RenderTargets& targets) {
  const Eigen::Matrix4f view = view_matrix(camera);
  const Lighting light{-(view.topLeftCorner<3, 3>() * scene.light_direction).normalized(),
                       scene.ambient, scene.diffuse};
  vertices_.clear();
  indices_.clear();
  for (const DrawItem& item : scene.items)
    if (item.rgba[3] > 0.0f) add_item(item, view, camera.zfar, light);

  // Alpha 0: the background's segment id.
  gl_.glClearColor(scene.background.x(), scene.background.y(), scene.background.z(), 0.0f);
  gl_.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl_.glLoadMatrixf(projection_matrix(camera).data());
  if (!indices_.empty()) {
    gl_.glVertexPointer(3, GL_FLOAT, sizeof(Vertex), &vertices_[0].x);
    gl_.glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(Vertex), vertices_[0].rgba);
    gl_.glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indices_.size()), GL_UNSIGNED_INT,
                       indices_.data());
  }
  read_back(camera, targets);
}

void GlSceneDrawer::read_back(const Camera& camera, const RenderTargets& targets) {
  const auto pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  if (targets.segmentation) {
    rgba_.resize(4 * pixels);
    gl_.glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data());
    for (int y = 0; y < height_; ++y) {  // GL's bottom row first: row y is image row height - 1 - y
      const std::uint8_t* from = rgba_.data() + 4 * static_cast<std::size_t>(y) * static_cast<std::size_t>(width_);
      const std::size_t to = static_cast<std::size_t>(height_ - 1 - y) * static_cast<std::size_t>(width_);
      for (int x = 0; x < width_; ++x, from += 4) {
        targets.segmentation[to + static_cast<std::size_t>(x)] = from[3];
        if (targets.rgb) std::copy(from, from + 3, targets.rgb + 3 * (to + static_cast<std::size_t>(x)));
      }
    }
  } else if (targets.rgb) {
    gl_.glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, targets.rgb);
    flip_rows(targets.rgb, width_, height_);
  }
  if (targets.depth) {
    depth_.resize(pixels);
    gl_.glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, depth_.data());
    const double n = camera.znear, f = camera.zfar;
    for (int y = 0; y < height_; ++y) {
      const float* from = depth_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width_);
      float* to = targets.depth + static_cast<std::size_t>(height_ - 1 - y) * static_cast<std::size_t>(width_);
      for (int x = 0; x < width_; ++x) to[x] = linear_depth(from[x], n, f);
    }
  }
}

}  // namespace rdsim::render
