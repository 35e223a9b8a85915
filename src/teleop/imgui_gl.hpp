#pragma once
// Dear ImGui's triangles and rdsim's images drawn through the window context's own GL table
// (rdsim/render/gl_api.hpp), with the fixed-function GL 1.1 pipeline: the packaged ImGui OpenGL
// backends call gl* by name, which in rdsim's process may resolve to libOSMesa's.
#include <cstdint>

#include "rdsim/render/gl_api.hpp"

struct ImDrawData;

namespace rdsim::teleop {

// An RGB texture of a fixed size, refilled each frame (the 3D view, a robot's camera).
class GlImage {
public:
  explicit GlImage(const render::GlApi& gl) : gl_(gl) {}
  ~GlImage();
  GlImage(const GlImage&) = delete;
  GlImage& operator=(const GlImage&) = delete;

  // Uploads width x height RGB bytes (row 0 at the top); (re)creates the texture on a new size.
  void upload(const std::uint8_t* rgb, int width, int height);
  // For ImGui::Image (0 before the first upload).
  void* id() const { return reinterpret_cast<void*>(static_cast<std::uintptr_t>(texture_)); }
  int width() const { return width_; }
  int height() const { return height_; }

private:
  const render::GlApi& gl_;
  GLuint texture_ = 0;
  int width_ = 0, height_ = 0;
};

class ImguiGl {
public:
  // Builds the font atlas texture; ImGui's context must exist.
  explicit ImguiGl(const render::GlApi& gl);
  ~ImguiGl();
  ImguiGl(const ImguiGl&) = delete;
  ImguiGl& operator=(const ImguiGl&) = delete;

  // Draws a frame's ImGui output over whatever the framebuffer holds.
  void render(const ImDrawData& data);

private:
  const render::GlApi& gl_;
  GLuint font_ = 0;
};

}  // namespace rdsim::teleop
