#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rdsim/render/camera.hpp"
#include "rdsim/render/render_targets.hpp"
#include "rdsim/render/scene.hpp"

namespace rdsim {

// Draws a Scene seen by a Camera into an RGB image of a fixed size. Each Renderer owns its own
// graphics context and buffers, so several can live in one process (one per env, or one per
// camera). A Renderer must be used from one thread at a time; it may be created on one thread
// and draw from another (its context is bound at the first frame). An egl renderer then keeps
// drawing from the thread of its first frame (EGL binds a context to one thread).
class Renderer {
public:
  virtual ~Renderer() = default;

  // Draws the scene once into the targets given. rdsim::Error when camera.width/height differ
  // from this renderer's size or the camera is unusable (see check_camera).
  virtual void render(const Scene& scene, const Camera& camera, const RenderTargets& targets) = 0;
  // Writes height x width x 3 bytes (RGB, row-major, row 0 = TOP of the image) to rgb_out.
  void render(const Scene& scene, const Camera& camera, std::uint8_t* rgb_out) {
    render(scene, camera, RenderTargets{.rgb = rgb_out});
  }

  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual std::string backend() const = 0;
  // The graphics implementation in use, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  virtual std::string device() const = 0;
};

// backend: one of renderer_backends() ("osmesa" is always built: CPU, no display needed; "egl"
// when built: GPU or Mesa software through EGL, no display needed), or "auto": the first of
// renderer_backends() that works here (egl when it can make a context, else osmesa).
// rdsim::Error for an unknown backend or a size outside 1..4096.
std::unique_ptr<Renderer> make_renderer(const std::string& backend, int width, int height);

std::vector<std::string> renderer_backends();

}  // namespace rdsim
