#include "imgui_gl.hpp"

#include <imgui.h>

#include <Eigen/Core>

namespace rdsim::teleop {

GlImage::~GlImage() {
  if (texture_) gl_.glDeleteTextures(1, &texture_);
}

void GlImage::upload(const std::uint8_t* rgb, int width, int height) {
  gl_.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (!texture_) gl_.glGenTextures(1, &texture_);
  gl_.glBindTexture(GL_TEXTURE_2D, texture_);
  if (width != width_ || height != height_) {
    gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl_.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    width_ = width;
    height_ = height;
  } else {
    gl_.glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb);
  }
}

ImguiGl::ImguiGl(const render::GlApi& gl) : gl_(gl) {
  ImGuiIO& io = ImGui::GetIO();
  io.BackendRendererName = "rdsim_gl11";
  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);
  gl_.glGenTextures(1, &font_);
  gl_.glBindTexture(GL_TEXTURE_2D, font_);
  gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(font_)));
}

ImguiGl::~ImguiGl() {
  if (font_) gl_.glDeleteTextures(1, &font_);
  ImGui::GetIO().Fonts->SetTexID(nullptr);
}

void ImguiGl::render(const ImDrawData& data) {
  // Framebuffer pixels per ImGui unit (HiDPI screens have more than one).
  const float sx = data.FramebufferScale.x, sy = data.FramebufferScale.y;
  const int fb_width = static_cast<int>(data.DisplaySize.x * sx), fb_height = static_cast<int>(data.DisplaySize.y * sy);
  if (fb_width <= 0 || fb_height <= 0) return;

  gl_.glViewport(0, 0, fb_width, fb_height);
  gl_.glEnable(GL_BLEND);
  gl_.glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  gl_.glDisable(GL_CULL_FACE);
  gl_.glDisable(GL_DEPTH_TEST);
  gl_.glDisable(GL_LIGHTING);
  gl_.glEnable(GL_SCISSOR_TEST);
  gl_.glEnable(GL_TEXTURE_2D);
  gl_.glShadeModel(GL_SMOOTH);
  gl_.glEnableClientState(GL_VERTEX_ARRAY);
  gl_.glEnableClientState(GL_TEXTURE_COORD_ARRAY);
  gl_.glEnableClientState(GL_COLOR_ARRAY);

  // ImGui's coordinates (top-left origin, y down) to clip space.
  const float l = data.DisplayPos.x, r = data.DisplayPos.x + data.DisplaySize.x;
  const float t = data.DisplayPos.y, b = data.DisplayPos.y + data.DisplaySize.y;
  Eigen::Matrix4f ortho = Eigen::Matrix4f::Identity();
  ortho(0, 0) = 2.0f / (r - l);
  ortho(1, 1) = 2.0f / (t - b);
  ortho(2, 2) = -1.0f;
  ortho(0, 3) = -(r + l) / (r - l);
  ortho(1, 3) = -(t + b) / (t - b);
  const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
  gl_.glMatrixMode(GL_MODELVIEW);
  gl_.glLoadMatrixf(identity.data());
  gl_.glMatrixMode(GL_PROJECTION);
  gl_.glLoadMatrixf(ortho.data());

  for (int n = 0; n < data.CmdListsCount; ++n) {
    const ImDrawList* list = data.CmdLists[n];
    const ImDrawVert* vertices = list->VtxBuffer.Data;
    const ImDrawIdx* indices = list->IdxBuffer.Data;
    gl_.glVertexPointer(2, GL_FLOAT, sizeof(ImDrawVert), &vertices->pos);
    gl_.glTexCoordPointer(2, GL_FLOAT, sizeof(ImDrawVert), &vertices->uv);
    gl_.glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(ImDrawVert), &vertices->col);
    for (int c = 0; c < list->CmdBuffer.Size; ++c) {
      const ImDrawCmd& cmd = list->CmdBuffer[c];
      if (cmd.UserCallback) {
        cmd.UserCallback(list, &cmd);
        continue;
      }
      // Clip rectangle in framebuffer pixels; GL's scissor origin is the bottom left.
      const float x0 = (cmd.ClipRect.x - l) * sx, y0 = (cmd.ClipRect.y - t) * sy;
      const float x1 = (cmd.ClipRect.z - l) * sx, y1 = (cmd.ClipRect.w - t) * sy;
      if (x1 <= x0 || y1 <= y0) continue;
      gl_.glScissor(static_cast<GLint>(x0), static_cast<GLint>(static_cast<float>(fb_height) - y1),
                    static_cast<GLsizei>(x1 - x0), static_cast<GLsizei>(y1 - y0));
      gl_.glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(reinterpret_cast<std::uintptr_t>(cmd.GetTexID())));
      gl_.glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(cmd.ElemCount),
                         sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT, indices + cmd.IdxOffset);
    }
  }
  gl_.glDisableClientState(GL_COLOR_ARRAY);
  gl_.glDisableClientState(GL_TEXTURE_COORD_ARRAY);
  gl_.glDisableClientState(GL_VERTEX_ARRAY);
  gl_.glDisable(GL_SCISSOR_TEST);
  gl_.glDisable(GL_TEXTURE_2D);
}

}  // namespace rdsim::teleop
