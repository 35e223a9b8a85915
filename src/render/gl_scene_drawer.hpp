#pragma once
// Draws a Scene into whatever GL context is current and reads the pixels back. Context-agnostic
// (plain GL 1.1 with client vertex arrays) so that every backend (OSMesa, EGL) shares it.
//
// Why transform and light on the CPU: with a software rasteriser every GL draw call and every
// matrix change costs about 2 us of state validation, more than transforming and lighting the
// ~1,500 vertices of a 20-item scene ourselves. So each frame becomes ONE draw call of eye-space
// positions with per-vertex colours (ambient + diffuse, Gouraud), and GL only clips, rasterises
// and depth-tests.
#include <cstdint>
#include <vector>

#include "rdsim/render/gl_api.hpp"
#include "rdsim/render/camera.hpp"
#include "rdsim/render/render_targets.hpp"
#include "rdsim/render/scene.hpp"
#include "unit_meshes.hpp"

namespace rdsim::render {

class GlSceneDrawer {
public:
  // The context must be current; GL state set here lives in that context.
  GlSceneDrawer(const GlApi& gl, int width, int height);
  GlSceneDrawer(const GlSceneDrawer&) = delete;
  GlSceneDrawer& operator=(const GlSceneDrawer&) = delete;

  // The drawer's context must be current. Draws once and reads back the targets given (row 0 =
  // top): colour from the colour buffer's RGB, segmentation from its alpha (each vertex carries
  // its item's id there, constant over each triangle, and nothing blends), depth from the depth
  // buffer, made linear.
  void draw(const Scene& scene, const Camera& camera, const RenderTargets& targets);

private:
  struct Vertex {
    float x, y, z;         // eye space
    std::uint8_t rgba[4];  // lit colour
  };
  struct Lighting {
    Eigen::Vector3f to_light;  // eye space, unit
    float ambient, diffuse;
  };

  // What each vertex of an item gets besides its position: the item's colour and segment id.
  struct Paint {
    Eigen::Vector3f rgb;
    std::uint8_t segment;
  };

  void add_item(const DrawItem& item, const Eigen::Matrix4f& view, float far_extent,
                const Lighting& light);
  void add_mesh(UnitMesh mesh, const Eigen::Matrix4f& model_view, const Paint& paint, const Lighting& light);
  // A loaded mesh (DrawShape::Mesh): the same transform, lighting and culling, 32-bit indices.
  void add_triangle_mesh(const TriangleMesh& mesh, const Eigen::Matrix4f& model_view, const Paint& paint,
                         const Lighting& light);
  // The colour buffer into rgb and/or segmentation, the depth buffer into depth (RenderTargets).
  void read_back(const Camera& camera, const RenderTargets& targets);
  // Back-face culling of the triangle (a, b, c) of vertices_ (indices absolute).
  void add_if_facing(GLuint a, GLuint b, GLuint c);

  const GlApi& gl_;
  int width_, height_;
  UnitMeshes meshes_;
  // Rebuilt every frame; kept to reuse their capacity.
  std::vector<Vertex> vertices_;
  std::vector<GLuint> indices_;
  // Read-back scratch (RGBA bytes, depth buffer values), kept to reuse their capacity.
  std::vector<std::uint8_t> rgba_;
  std::vector<float> depth_;
};

}  // namespace rdsim::render
