#pragma once
// What every GL backend (OSMesa, EGL) shares: the image size, the GL entry points of its
// context, the device name, the scene drawer and render()'s checks. A backend creates its context,
// calls start(), and says how to make the context current and how to release it.
#include <functional>
#include <optional>
#include <string>

#include "rdsim/render/gl_api.hpp"
#include "gl_scene_drawer.hpp"
#include "rdsim/render/renderer.hpp"

namespace rdsim::render {

class GlRenderer : public Renderer {
public:
  // rdsim::Error when the camera's size is not this renderer's or the camera is unusable.
  void render(const Scene& scene, const Camera& camera, const RenderTargets& targets) final;
  using Renderer::render;

  int width() const final { return width_; }
  int height() const final { return height_; }
  std::string device() const final { return device_; }

protected:
  GlRenderer(int width, int height) : width_(width), height_(height) {}
  GlRenderer(const GlRenderer&) = delete;  // a renderer owns its context
  GlRenderer& operator=(const GlRenderer&) = delete;

  // For the backend's constructor, once its context exists: makes it current, fetches the GL
  // entry points through `get_proc`, runs `setup` (the backend's own, e.g. a framebuffer object)
  // and prepares the drawer, then unbinds the context again: the first frame binds it in the
  // thread that draws, which need not be the one that made the renderer (a VecEnv worker). On
  // failure it calls release() and rethrows (rdsim::Error naming a missing GL function, or what
  // `setup` threw).
  void start(GlGetProc get_proc, const std::function<void()>& setup = nullptr);
  const GlApi& gl() const { return gl_; }

  // Makes the backend's context current in this thread; cheap when it already is (another
  // Renderer in this thread may have made its own context current since our last frame).
  virtual void make_current() = 0;
  // Leaves the backend's context current in no thread (it is current in this one).
  virtual void unbind() = 0;
  // Frees the backend's context (its destructor calls it too).
  virtual void release() = 0;

  const int width_, height_;

private:
  GlApi gl_;
  std::string device_;
  std::optional<GlSceneDrawer> drawer_;
};

}  // namespace rdsim::render
