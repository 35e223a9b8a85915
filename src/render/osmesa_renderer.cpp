// CPU rendering through Mesa's off-screen interface: no display, no GPU, works on CI.
#include <GL/osmesa.h>

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends.hpp"
#include "rdsim/render/gl_api.hpp"
#include "gl_scene_drawer.hpp"
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
  if (!ctx) throw std::runtime_error("renderer: OSMesa could not create a GL context");
  return ctx;
}

class OsmesaRenderer final : public Renderer {
public:
  OsmesaRenderer(int width, int height)
      : width_(width), height_(height),
        color_(static_cast<size_t>(width) * static_cast<size_t>(height) * 4),
        ctx_(create_context()) {
    try {
      make_current();
      gl_ = load_gl_api(osmesa_proc);
      const char* renderer = reinterpret_cast<const char*>(gl_.glGetString(GL_RENDERER));
      device_ = renderer ? renderer : "unknown";
      drawer_.emplace(gl_, width_, height_);
    } catch (...) {
      OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
      OSMesaDestroyContext(ctx_);
      throw;
    }
  }

  ~OsmesaRenderer() override {
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(ctx_);
  }

  OsmesaRenderer(const OsmesaRenderer&) = delete;
  OsmesaRenderer& operator=(const OsmesaRenderer&) = delete;

  void render(const Scene& scene, const Camera& camera, std::uint8_t* rgb_out) override {
    if (camera.width != width_ || camera.height != height_)
      throw Error("renderer: camera is " + std::to_string(camera.width) + "x" +
                  std::to_string(camera.height) + " but the renderer was made for " +
                  std::to_string(width_) + "x" + std::to_string(height_));
    check_camera(camera);
    make_current();
    drawer_->draw(scene, camera, rgb_out);
  }

  int width() const override { return width_; }
  int height() const override { return height_; }
  std::string backend() const override { return "osmesa"; }
  std::string device() const override { return device_; }

private:
  // Another Renderer in this thread may have made its own context current since our last frame.
  void make_current() {
    if (OSMesaGetCurrentContext() == ctx_) return;
    if (!OSMesaMakeCurrent(ctx_, color_.data(), GL_UNSIGNED_BYTE, width_, height_))
      throw std::runtime_error("renderer: OSMesaMakeCurrent failed");
  }

  int width_, height_;
  std::vector<std::uint8_t> color_;  // OSMesa's colour buffer (RGBA, bottom-up)
  OSMesaContext ctx_;
  GlApi gl_;
  std::string device_;
  std::optional<GlSceneDrawer> drawer_;
};

}  // namespace

std::unique_ptr<Renderer> make_osmesa_renderer(int width, int height) {
  return std::make_unique<OsmesaRenderer>(width, height);
}

}  // namespace rdsim::render
