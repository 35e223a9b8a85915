// CPU rendering through Mesa's off-screen interface: no display, no GPU, works on CI.
#include <GL/osmesa.h>
#include <malloc.h>

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends.hpp"
#include "gl_api.hpp"
#include "gl_scene_drawer.hpp"
#include "rdsim/error.hpp"

namespace rdsim::render {
namespace {

GlProc osmesa_proc(const char* name) { return reinterpret_cast<GlProc>(OSMesaGetProcAddress(name)); }

// Process-wide settings that make per-frame software rendering cheap. They must be in place
// before Mesa creates its first context (llvmpipe reads LP_NUM_THREADS once, when it starts), so
// they are applied here, once, rather than left to every program that renders. Measured on the
// 2-core dev box, Release, one thread:
//  - Mesa allocates and frees large scratch buffers on every draw. By default glibc gives the top
//    of the heap back to the OS each time (brk) and faults it back in next frame (perf: 26% of the
//    time in page faults), and mmaps/unmaps buffers above 128 KiB. A 512 MiB trim threshold and the
//    largest mmap threshold keep them in the heap: inmoov_tomato 64x64 render 2,600 -> 500 us per
//    frame; jaka_button 224x224 750 -> 2,300 steps/s.
//  - llvmpipe's rasteriser threads (one per core by default) cost more in hand-offs than they save
//    on images this small, and an env step must stay on one thread: LP_NUM_THREADS=0 draws in the
//    calling thread (jaka_button 64x64: 3,100 -> 11,500 steps/s). A value set by the user wins.
void tune_process_for_software_rendering() {
  static const bool once = [] {
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest; the call above froze it at 128 KiB
    setenv("LP_NUM_THREADS", "0", 0);
    return true;
  }();
  (void)once;
}

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
