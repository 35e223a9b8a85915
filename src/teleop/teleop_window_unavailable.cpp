// Built instead of teleop_window.cpp when GLFW or Dear ImGui is missing (CMakeLists.txt).
#include "rdsim/core/error.hpp"
#include "rdsim/teleop/teleop_window.hpp"

namespace rdsim {

bool teleop_window_available() { return false; }

void require_teleop_window() {
  throw Error("teleop: this rdsim was built without GLFW and Dear ImGui (install libglfw3-dev and libimgui-dev, "
              "then rebuild)");
}

void run_teleop_window(TeleopSession&, SceneMirror&, const TeleopWindowOptions&) { require_teleop_window(); }

}  // namespace rdsim
