#pragma once
// The renderer backends compiled into this build. Adding one (e.g. EGL, see EGL.md) is a new
// <name>_renderer.cpp defining its factory plus one entry in kBackends (renderer_factory.cpp).
#include <memory>

#include "rdsim/renderer.hpp"

namespace rdsim::render {

std::unique_ptr<Renderer> make_osmesa_renderer(int width, int height);

}  // namespace rdsim::render
