#pragma once
// The GL entry points rdsim draws with, fetched through the context's GetProcAddress instead of
// linked by name: libOSMesa, the EGL backend (GLVND's libOpenGL) and a window's GLX (the
// teleoperation window) all export gl* symbols, and only a per-context table lets them live in one
// process. The scene drawer uses the first group; the window (src/teleop) also the second, for
// textures and Dear ImGui's triangles.
#include <GL/gl.h>

namespace rdsim::render {

// All GL 1.1: their types come from the prototypes in gl.h (decltype links nothing).
#define RDSIM_GL_FUNCTIONS(X)                                                                \
  X(glGetString) X(glGetError) X(glViewport) X(glClearColor) X(glClear) X(glEnable)          \
  X(glDisable) X(glShadeModel) X(glCullFace) X(glFrontFace) X(glMatrixMode) X(glLoadMatrixf) \
  X(glEnableClientState) X(glVertexPointer) X(glColorPointer) X(glDrawElements)              \
  X(glPixelStorei) X(glReadPixels)                                                             \
  X(glBlendFunc) X(glScissor) X(glDisableClientState) X(glTexCoordPointer) X(glGenTextures)  \
  X(glDeleteTextures) X(glBindTexture) X(glTexParameteri) X(glTexImage2D) X(glTexSubImage2D) \
  X(glReadBuffer)

struct GlApi {
#define RDSIM_GL_MEMBER(name) decltype(&::name) name = nullptr;
  RDSIM_GL_FUNCTIONS(RDSIM_GL_MEMBER)
#undef RDSIM_GL_MEMBER
};

using GlProc = void (*)();
using GlGetProc = GlProc (*)(const char* name);

// Fills every entry from get_proc; rdsim::Error naming the first missing function.
GlApi load_gl_api(GlGetProc get_proc);

}  // namespace rdsim::render
