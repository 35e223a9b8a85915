#pragma once
// The renderer backends compiled into this build. Adding one is a new <name>_renderer.cpp
// defining its factory plus one entry in kBackends (renderer.cpp).
#include <memory>

#include "rdsim/render/renderer.hpp"

namespace rdsim::render {

// Mesa llvmpipe settings every software backend applies before its first context (software_gl.cpp).
void tune_process_for_software_rendering();

std::unique_ptr<Renderer> make_osmesa_renderer(int width, int height);

#ifdef RDSIM_HAVE_EGL
// rdsim::Error "egl renderer: no usable EGL device (...)" when no EGL display or context works.
std::unique_ptr<Renderer> make_egl_renderer(int width, int height);
#endif

}  // namespace rdsim::render
