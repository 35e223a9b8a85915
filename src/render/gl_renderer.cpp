#include "gl_renderer.hpp"

#include "rdsim/core/assert.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim::render {

void GlRenderer::render(const Scene& scene, const Camera& camera, const RenderTargets& targets) {
  if (camera.width != width_ || camera.height != height_)
    throw Error("renderer: camera is " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                " but the renderer was made for " + std::to_string(width_) + "x" + std::to_string(height_));
  check_camera(camera);
  RDSIM_ASSERT(drawer_.has_value(), "GlRenderer: the backend's constructor did not call start()");
  make_current();
  drawer_->draw(scene, camera, targets);
}

void GlRenderer::start(GlGetProc get_proc, const std::function<void()>& setup) {
  try {
    make_current();
    gl_ = load_gl_api(get_proc);
    const char* renderer = reinterpret_cast<const char*>(gl_.glGetString(GL_RENDERER));
    device_ = renderer ? renderer : "unknown";
    if (setup) setup();
    drawer_.emplace(gl_, width_, height_);
    unbind();
  } catch (...) {
    release();
    throw;
  }
}

}  // namespace rdsim::render
