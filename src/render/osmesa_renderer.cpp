// CPU rendering through Mesa's off-screen interface: no display, no GPU, works on CI.
#include <GL/osmesa.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "backends.hpp"
#include "gl_renderer.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim::render {
namespace {

GlProc osmesa_proc(const char* name) { return reinterpret_cast<GlProc>(OSMesaGetProcAddress(name)); }

OSMesaContext create_context() {
  tune_process_for_software_rendering();
  // Fixed-function GL with vertex buffers is all the drawer needs: ask for a 2.1 compatibility
  // context, and fall back to the old entry point on an OSMesa without context attributes.
  const int attribs[] = {OSMESA_FORMAT,        OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,    24,
                         OSMESA_STENCIL_BITS,  0,
                         OSMESA_ACCUM_BITS,    0,
                         OSMESA_PROFILE,       OSMESA_COMPAT_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION, 2,
                         OSMESA_CONTEXT_MINOR_VERSION, 1,
                         0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx) ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!ctx) throw Error("renderer: OSMesa could not create a GL context");
  return ctx;
}

class OsmesaRenderer final : public GlRenderer {
public:
  OsmesaRenderer(int width, int height)
      : GlRenderer(width, height),
        color_(static_cast<size_t>(width) * static_cast<size_t>(height) * 4),
        ctx_(create_context()) {
    start(osmesa_proc);
  }
  ~OsmesaRenderer() override { release(); }

  std::string backend() const override { return "osmesa"; }

private:
  void make_current() override {
    if (OSMesaGetCurrentContext() == ctx_) return;
    if (!OSMesaMakeCurrent(ctx_, color_.data(), GL_UNSIGNED_BYTE, width_, height_))
      throw Error("renderer: OSMesaMakeCurrent failed");
  }

  void unbind() override { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }

  void release() override {
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(ctx_);
  }

  std::vector<std::uint8_t> color_;  // OSMesa's colour buffer (RGBA, bottom-up)
  OSMesaContext ctx_;
};

}  // namespace

std::unique_ptr<Renderer> make_osmesa_renderer(int width, int height) {
  return std::make_unique<OsmesaRenderer>(width, height);
}

}  // namespace rdsim::render
