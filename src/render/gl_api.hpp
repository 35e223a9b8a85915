#pragma once
// The GL entry points the scene drawer uses, fetched through the backend's GetProcAddress
// instead of linked by name: libOSMesa and a future EGL backend (GLVND's libOpenGL) both export
// gl* symbols, and only a per-context table lets both live in one process.
#include <GL/gl.h>

namespace rdsim::render {

// All GL 1.1: their types come from the prototypes in gl.h (decltype links nothing).
#define RDSIM_GL_FUNCTIONS(X)                                                                \
  X(glGetString) X(glGetError) X(glViewport) X(glClearColor) X(glClear) X(glEnable)          \
  X(glDisable) X(glShadeModel) X(glCullFace) X(glFrontFace) X(glMatrixMode) X(glLoadMatrixf) \
  X(glEnableClientState) X(glVertexPointer) X(glColorPointer) X(glDrawElements)              \
  X(glPixelStorei) X(glReadPixels)

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
