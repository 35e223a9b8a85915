#pragma once
#include <string>

#include "rdsim/teleop/scene_mirror.hpp"
#include "rdsim/teleop/teleop_session.hpp"

// The teleoperation window of `rdsim teleop` (GLFW + Dear ImGui, OpenGL): the scene from a camera
// the mouse orbits (drag) and zooms (wheel), the robot's first-person cameras, and the controls:
//   keys       W/S or Up/Down: +x/-x, A/D or Left/Right: +y/-y, Q/E or PageUp/PageDown: +z/-z — the
//              env's own actions (Discrete(6) moves, or a full Box(3) step along the axis), one per
//              key press and per auto-repeat: what a demonstration records;
//              R: Record / Stop, X: Discard, N: Reset (new episode), P: screenshot, Esc: quit;
//   sliders    the original's two modes through RobotControl: effector target x/y/z within the
//              workspace, and one slider per movable joint within its limits (not while recording);
//   status     reward, return, distance, success / collision / out of bounds, step count, recording.
// Built only with GLFW and Dear ImGui (libglfw3-dev, libimgui-dev); otherwise run_teleop_window
// says so. Headless machines run it under Xvfb.
namespace rdsim {

struct TeleopWindowOptions {
  std::string title = "rdsim teleop";
  int width = 1280, height = 800;               // window size (screen pixels)
  int view_width = 760, view_height = 440;      // the 3D view's image
  int camera_width = 320, camera_height = 240;  // each first-person camera's image
  std::string renderer = "osmesa";              // backend of the 3D view (render/renderer.hpp)
  std::string screenshot_path = "teleop.png";   // where P writes the window as PNG
  long long max_frames = 0;                     // stop after this many frames; 0 = until closed
};

// Whether this build has the window (GLFW and Dear ImGui were found).
bool teleop_window_available();
// rdsim::Error saying what to install when it has not.
void require_teleop_window();

// Runs the window until it is closed (Esc, the close button) or max_frames. rdsim::Error when the
// build has no window or no window can be opened (no display: run it under Xvfb).
void run_teleop_window(TeleopSession& session, SceneMirror& mirror, const TeleopWindowOptions& options);

}  // namespace rdsim
