#include "rdsim/render/gl_api.hpp"

#include <string>

#include "rdsim/core/error.hpp"

namespace rdsim::render {
namespace {

template <typename Fn>
void load(Fn& slot, GlGetProc get_proc, const char* name) {
  slot = reinterpret_cast<Fn>(get_proc(name));
  if (!slot) throw Error(std::string("renderer: GL function ") + name + " not available");
}

}  // namespace

GlApi load_gl_api(GlGetProc get_proc) {
  GlApi gl;
#define RDSIM_GL_LOAD(name) load(gl.name, get_proc, #name);
  RDSIM_GL_FUNCTIONS(RDSIM_GL_LOAD)
#undef RDSIM_GL_LOAD
  return gl;
}

}  // namespace rdsim::render
