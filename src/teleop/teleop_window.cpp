// The teleoperation window: GLFW for the window and input, Dear ImGui for the controls, rdsim's
// renderer for the 3D view and the env's RobotControl for the robot's own cameras.
#include "rdsim/teleop/teleop_window.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>
#include <thread>
#include <vector>

#include "imgui_gl.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/render/png.hpp"
#include "rdsim/render/renderer.hpp"

namespace rdsim {
namespace {

// Key presses (and auto-repeats) in the order they came, for the frame loop.
std::deque<int> g_keys;
std::string g_glfw_error;

void on_key(GLFWwindow*, int key, int /*scancode*/, int action, int /*mods*/) {
  if (action == GLFW_PRESS || action == GLFW_REPEAT) g_keys.push_back(key);
}

void on_glfw_error(int /*code*/, const char* text) { g_glfw_error = text ? text : "unknown"; }

bool move_for_key(int key, Move& move) {
  switch (key) {
    case GLFW_KEY_W: case GLFW_KEY_UP: move = Move::PlusX; return true;
    case GLFW_KEY_S: case GLFW_KEY_DOWN: move = Move::MinusX; return true;
    case GLFW_KEY_A: case GLFW_KEY_LEFT: move = Move::PlusY; return true;
    case GLFW_KEY_D: case GLFW_KEY_RIGHT: move = Move::MinusY; return true;
    case GLFW_KEY_Q: case GLFW_KEY_PAGE_UP: move = Move::PlusZ; return true;
    case GLFW_KEY_E: case GLFW_KEY_PAGE_DOWN: move = Move::MinusZ; return true;
    default: return false;
  }
}

// The window, its GL context and ImGui, torn down in the right order.
class Window {
public:
  explicit Window(const TeleopWindowOptions& o) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit())
      throw Error("teleop: cannot open a window (" + g_glfw_error +
                  "); on a machine without a display run it under Xvfb: xvfb-run -s '-screen 0 1280x800x24' rdsim teleop ...");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    window_ = glfwCreateWindow(o.width, o.height, o.title.c_str(), nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw Error("teleop: cannot create an OpenGL window (" + g_glfw_error + ")");
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(1);
    gl_ = render::load_gl_api(reinterpret_cast<render::GlGetProc>(&glfwGetProcAddress));
    g_keys.clear();
    glfwSetKeyCallback(window_, on_key);  // before ImGui's, which chains to it
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini: the layout is fixed
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    imgui_ = std::make_unique<teleop::ImguiGl>(gl_);
  }
  ~Window() {
    images_.clear();
    imgui_.reset();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Makes the window's context current again: rendering offscreen (OSMesa) and GLX share Mesa's
  // dispatch, so the window's context is released and re-bound rather than assumed current.
  void bind() {
    glfwMakeContextCurrent(nullptr);
    glfwMakeContextCurrent(window_);
  }
  teleop::GlImage& image(std::size_t i) {
    while (images_.size() <= i) images_.push_back(std::make_unique<teleop::GlImage>(gl_));
    return *images_[i];
  }

  GLFWwindow* handle() const { return window_; }
  const render::GlApi& gl() const { return gl_; }
  teleop::ImguiGl& imgui() { return *imgui_; }

private:
  GLFWwindow* window_ = nullptr;
  render::GlApi gl_;
  std::unique_ptr<teleop::ImguiGl> imgui_;
  std::vector<std::unique_ptr<teleop::GlImage>> images_;
};

enum class Mode { Keys, Effector, Joints };

constexpr float kEffectorTolerance = 0.002f;  // m: the slider target counts as reached
constexpr float kJointTolerance = 0.005f;     // rad (m for prismatic joints)
constexpr int kDriveSteps = 480;              // env steps a slider change may take at most (2 s)

// The frame loop's state: what the person set, what the env last reported, and the pictures.
class TeleopUi {
public:
  TeleopUi(TeleopSession& session, SceneMirror& mirror, const TeleopWindowOptions& o, Window& window)
      : session_(session),
        mirror_(mirror),
        options_(o),
        window_(window),
        info_(session.control().robot_info()),
        orbit_(mirror.main_view()),
        view_renderer_(make_renderer(o.renderer, o.view_width, o.view_height)),
        camera_images_(info_.cameras.size()) {
    view_pixels_.resize(static_cast<std::size_t>(o.view_width) * static_cast<std::size_t>(o.view_height) * 3);
    refresh_state();
    effector_target_ = state_.effector_position;
    joint_targets_ = state_.joint_positions;
  }

  // One frame: input, env steps, pictures, controls. False once the person quits.
  bool frame();
  // Prints what a new saved demonstration's message says (the terminal keeps a record).
  void report_saves();

private:
  void refresh_state();
  void handle_keys();
  void toggle_record();
  void reset();
  void drive_sliders();
  void render_pictures();
  void draw_view();
  void draw_cameras();
  void draw_controls();
  void draw_status();
  void draw_sliders();
  void write_screenshot();
  // Cameras on the robot (an eye, the wrist); world-fixed ones ("scene") the 3D view replaces.
  bool first_person(std::size_t camera) const { return !info_.cameras[camera].link.empty(); }
  template <class F>
  void guarded(F&& what);

  TeleopSession& session_;
  SceneMirror& mirror_;
  const TeleopWindowOptions& options_;
  Window& window_;
  const RobotInfo& info_;
  OrbitView orbit_;
  std::unique_ptr<Renderer> view_renderer_;
  std::vector<std::uint8_t> view_pixels_;
  std::vector<Image> camera_images_;
  RobotSnapshot state_;
  bool state_changed_ = true, view_changed_ = true;
  bool quit_ = false, screenshot_ = false;
  Mode mode_ = Mode::Keys;
  Eigen::Vector3f effector_target_ = Eigen::Vector3f::Zero();
  Eigen::VectorXf joint_targets_;
  int drive_steps_left_ = 0;
  std::string error_;  // the last refused action, shown until the next one succeeds
  long long reported_saves_ = -1;
};

template <class F>
void TeleopUi::guarded(F&& what) {
  try {
    what();
    error_.clear();
  } catch (const Error& e) {
    error_ = e.what();
  }
}

void TeleopUi::refresh_state() {
  state_ = session_.control().robot_state();
  mirror_.update(state_);
  state_changed_ = true;
}

void TeleopUi::reset() {
  guarded([&] { session_.reset(); });
  refresh_state();
  effector_target_ = state_.effector_position;
  joint_targets_ = state_.joint_positions;
  drive_steps_left_ = 0;
}

void TeleopUi::toggle_record() {
  guarded([&] {
    if (session_.status().recording) {
      session_.stop_recording();
    } else {
      mode_ = Mode::Keys;  // demonstrations hold the env's own actions
      drive_steps_left_ = 0;
      session_.start_recording();
    }
  });
  refresh_state();
}

void TeleopUi::handle_keys() {
  const bool typing = ImGui::GetIO().WantCaptureKeyboard;
  while (!g_keys.empty()) {
    const int key = g_keys.front();
    g_keys.pop_front();
    Move move;
    if (key == GLFW_KEY_ESCAPE) {
      quit_ = true;
    } else if (typing) {
      continue;  // an ImGui text field has the keys
    } else if (move_for_key(key, move)) {
      mode_ = Mode::Keys;
      drive_steps_left_ = 0;
      bool stepped = false;
      guarded([&] { stepped = session_.act(move); });
      if (stepped) refresh_state();
    } else if (key == GLFW_KEY_G || key == GLFW_KEY_SPACE) {
      if (!session_.status().has_gripper) continue;
      mode_ = Mode::Keys;
      drive_steps_left_ = 0;
      bool stepped = false;
      guarded([&] { stepped = session_.toggle_gripper(); });
      if (stepped) refresh_state();
    } else if (key == GLFW_KEY_R) {
      if (session_.can_record()) toggle_record();
    } else if (key == GLFW_KEY_X) {
      session_.discard_recording();
    } else if (key == GLFW_KEY_N) {
      reset();
    } else if (key == GLFW_KEY_P) {
      screenshot_ = true;
    }
  }
}

// Slider modes: one RobotControl step per frame towards the targets until they are reached (or a
// while after the last change, when a joint cannot get there).
void TeleopUi::drive_sliders() {
  if (mode_ == Mode::Keys || drive_steps_left_ <= 0 || session_.status().ended || session_.status().recording) return;
  bool stepped = false;
  if (mode_ == Mode::Effector) {
    if ((state_.effector_position - effector_target_).norm() < kEffectorTolerance) {
      drive_steps_left_ = 0;
      return;
    }
    guarded([&] { stepped = session_.move_effector(effector_target_); });
  } else {
    if ((state_.joint_positions - joint_targets_).cwiseAbs().maxCoeff() < kJointTolerance) {
      drive_steps_left_ = 0;
      return;
    }
    guarded([&] { stepped = session_.set_joint_targets(joint_targets_); });
  }
  --drive_steps_left_;
  if (stepped) refresh_state();
}

void TeleopUi::render_pictures() {
  if (state_changed_ || view_changed_) {
    view_renderer_->render(mirror_.scene(), make_orbit_camera(orbit_, options_.view_width, options_.view_height),
                           view_pixels_.data());
  }
  if (state_changed_) {
    for (std::size_t i = 0; i < camera_images_.size(); ++i)
      if (first_person(i)) guarded([&] {
        session_.control().camera_image(static_cast<int>(i), options_.camera_width, options_.camera_height, camera_images_[i]);
      });
  }
  // Offscreen rendering made its own context current: the window's uploads come after.
  window_.bind();
  if (state_changed_ || view_changed_) window_.image(0).upload(view_pixels_.data(), options_.view_width, options_.view_height);
  if (state_changed_)
    for (std::size_t i = 0; i < camera_images_.size(); ++i)
      if (!camera_images_[i].rgb.empty())
        window_.image(i + 1).upload(camera_images_[i].rgb.data(), camera_images_[i].width, camera_images_[i].height);
  state_changed_ = view_changed_ = false;
}

void TeleopUi::draw_view() {
  const float w = static_cast<float>(options_.view_width), h = static_cast<float>(options_.view_height);
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::Begin("Scene (drag: orbit, wheel: zoom)", nullptr,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse);
  ImGui::Image(window_.image(0).id(), ImVec2(w, h));
  if (ImGui::IsItemHovered()) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.MouseDown[0] && (io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f)) {
      orbit_.yaw_deg -= 0.3f * io.MouseDelta.x;
      orbit_.pitch_deg = std::clamp(orbit_.pitch_deg - 0.3f * io.MouseDelta.y, -89.0f, 89.0f);
      view_changed_ = true;
    }
    if (io.MouseWheel != 0.0f) {
      orbit_.distance = std::clamp(orbit_.distance * std::pow(0.9f, io.MouseWheel), 0.2f, 10.0f);
      view_changed_ = true;
    }
  }
  ImGui::End();
}

void TeleopUi::draw_cameras() {
  bool any = false;
  for (std::size_t i = 0; i < info_.cameras.size(); ++i) any = any || first_person(i);
  if (!any) return;
  ImGui::SetNextWindowPos(ImVec2(8, static_cast<float>(options_.view_height) + 52.0f), ImGuiCond_Always);
  ImGui::Begin("Robot cameras", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse);
  bool first = true;
  for (std::size_t i = 0; i < info_.cameras.size(); ++i) {
    if (!first_person(i)) continue;
    if (!first) ImGui::SameLine();
    first = false;
    ImGui::BeginGroup();
    ImGui::TextUnformatted(info_.cameras[i].name.c_str());
    const teleop::GlImage& image = window_.image(i + 1);
    ImGui::Image(image.id(), ImVec2(static_cast<float>(options_.camera_width), static_cast<float>(options_.camera_height)));
    ImGui::EndGroup();
  }
  ImGui::End();
}

void TeleopUi::draw_status() {
  const TeleopStatus& s = session_.status();
  const Spec& spec = session_.env().spec();
  ImGui::Text("env %s   actions %s", spec.env_name.c_str(), describe_action_space(spec.action).c_str());
  ImGui::Text("step %d / %d   reward %.3f   return %.2f", s.steps, spec.max_episode_steps, s.last_reward, s.episode_return);
  ImGui::Text("distance to target %.3f m", s.info.distance);
  if (s.has_gripper) ImGui::Text("gripper %s (G or space)", s.gripper_open ? "open" : "closed");
  if (mirror_.target_item() >= 0) {  // a target among several alike (inmoov_tomato): say which the mark is
    const Eigen::Vector4f c = SceneMirror::target_colour();
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(c[0], c[1], c[2], c[3]), "(the yellow one)");
  }
  const ImVec4 green(0.3f, 0.9f, 0.3f, 1.0f), red(1.0f, 0.35f, 0.3f, 1.0f), grey(0.6f, 0.6f, 0.6f, 1.0f);
  ImGui::TextColored(s.info.success ? green : grey, "success");
  ImGui::SameLine();
  ImGui::TextColored(s.info.collision ? red : grey, "collision");
  ImGui::SameLine();
  ImGui::TextColored(s.info.out_of_bounds ? red : grey, "out of bounds");
  ImGui::SameLine();
  ImGui::TextColored(s.ended ? red : grey, s.truncated ? "step limit" : "ended");
  ImGui::Separator();
  if (ImGui::Button("Reset (N)")) reset();
  ImGui::SameLine();
  ImGui::BeginDisabled(!session_.can_record());
  if (ImGui::Button(s.recording ? "Stop (R)" : "Record (R)")) toggle_record();
  ImGui::SameLine();
  ImGui::BeginDisabled(!s.recording);
  if (ImGui::Button("Discard (X)")) session_.discard_recording();
  ImGui::EndDisabled();
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Button("Screenshot (P)")) screenshot_ = true;
  if (s.recording)
    ImGui::TextColored(red, "RECORDING  %d steps", s.recorded_steps);
  else if (session_.can_record())
    ImGui::Text("demonstrations saved: %lld", s.saved_episodes);
  else
    ImGui::TextColored(grey, "not recording (rdsim teleop --record FILE)");
  if (!s.message.empty()) ImGui::TextWrapped("%s", s.message.c_str());
  if (!error_.empty()) ImGui::TextColored(red, "%s", error_.c_str());
}

void TeleopUi::draw_sliders() {
  const bool recording = session_.status().recording;
  int mode = static_cast<int>(mode_);
  ImGui::TextUnformatted("Drive with");
  ImGui::RadioButton("keys: the env's actions (recorded)", &mode, 0);
  ImGui::BeginDisabled(recording);
  ImGui::RadioButton("effector target x/y/z", &mode, 1);
  ImGui::SameLine();
  ImGui::RadioButton("joints", &mode, 2);
  if (static_cast<Mode>(mode) != mode_) {
    mode_ = static_cast<Mode>(mode);
    effector_target_ = state_.effector_position;
    joint_targets_ = state_.joint_positions;
  }
  ImGui::TextDisabled(session_.status().has_gripper ? "W/S x  A/D y  Q/E z  (arrows, PageUp/Down)  G gripper"
                                                    : "W/S x  A/D y  Q/E z  (arrows, PageUp/Down)");
  ImGui::Separator();
  ImGui::TextUnformatted("Effector target (m, world frame)");
  const char* axes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    float v = mode_ == Mode::Effector ? effector_target_[k] : state_.effector_position[k];
    if (ImGui::SliderFloat(axes[k], &v, info_.workspace.min()[k], info_.workspace.max()[k], "%.3f")) {
      if (mode_ != Mode::Effector) {
        mode_ = Mode::Effector;
        effector_target_ = state_.effector_position;
      }
      effector_target_[k] = v;
      drive_steps_left_ = kDriveSteps;
    }
  }
  ImGui::Separator();
  ImGui::Text("Joints (%zu)", info_.joints.size());
  ImGui::BeginChild("joints", ImVec2(0, 0), true);
  for (std::size_t j = 0; j < info_.joints.size(); ++j) {
    const JointInfo& joint = info_.joints[j];
    const float lo = std::isfinite(joint.lower) ? joint.lower : -3.14159f;
    const float hi = std::isfinite(joint.upper) ? joint.upper : 3.14159f;
    const auto i = static_cast<Eigen::Index>(j);
    float v = mode_ == Mode::Joints ? joint_targets_[i] : state_.joint_positions[i];
    if (ImGui::SliderFloat(joint.name.c_str(), &v, lo, hi, "%.3f")) {
      if (mode_ != Mode::Joints) {
        mode_ = Mode::Joints;
        joint_targets_ = state_.joint_positions;
      }
      joint_targets_[i] = v;
      drive_steps_left_ = kDriveSteps;
    }
  }
  ImGui::EndChild();
  ImGui::EndDisabled();
}

void TeleopUi::draw_controls() {
  const float x = static_cast<float>(options_.view_width) + 40.0f;
  ImGui::SetNextWindowPos(ImVec2(x, 8), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(std::max(300.0f, static_cast<float>(options_.width) - x - 8.0f),
                                  static_cast<float>(options_.height) - 16.0f),
                           ImGuiCond_Always);
  ImGui::Begin("Control", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoResize);
  draw_status();
  ImGui::Separator();
  draw_sliders();
  ImGui::End();
}

void TeleopUi::write_screenshot() {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_.handle(), &w, &h);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  const render::GlApi& gl = window_.gl();
  gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.glReadBuffer(GL_BACK);
  gl.glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  const std::size_t row = static_cast<std::size_t>(w) * 3;  // GL rows go bottom-up
  for (int top = 0, bottom = h - 1; top < bottom; ++top, --bottom)
    std::swap_ranges(rgb.begin() + static_cast<long>(row) * top, rgb.begin() + static_cast<long>(row) * (top + 1),
                     rgb.begin() + static_cast<long>(row) * bottom);
  guarded([&] { write_png(options_.screenshot_path, w, h, 3, rgb.data()); });
  if (error_.empty()) {
    std::printf("rdsim teleop: wrote %s (%dx%d)\n", options_.screenshot_path.c_str(), w, h);
    std::fflush(stdout);
  }
}

void TeleopUi::report_saves() {
  if (reported_saves_ >= 0 && session_.status().saved_episodes > reported_saves_) {
    std::printf("rdsim teleop: %s\n", session_.status().message.c_str());
    std::fflush(stdout);
  }
  reported_saves_ = session_.status().saved_episodes;
}

bool TeleopUi::frame() {
  report_saves();
  glfwPollEvents();
  if (glfwWindowShouldClose(window_.handle())) return false;
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  handle_keys();
  drive_sliders();
  render_pictures();
  draw_view();
  draw_cameras();
  draw_controls();
  ImGui::Render();

  int w = 0, h = 0;
  glfwGetFramebufferSize(window_.handle(), &w, &h);
  const render::GlApi& gl = window_.gl();
  gl.glViewport(0, 0, w, h);
  gl.glClearColor(0.12f, 0.12f, 0.14f, 1.0f);
  gl.glClear(GL_COLOR_BUFFER_BIT);
  window_.imgui().render(*ImGui::GetDrawData());
  if (screenshot_) {
    write_screenshot();
    screenshot_ = false;
  }
  glfwSwapBuffers(window_.handle());
  return !quit_;
}

}  // namespace

bool teleop_window_available() { return true; }
void require_teleop_window() {}

void run_teleop_window(TeleopSession& session, SceneMirror& mirror, const TeleopWindowOptions& options) {
  Window window(options);
  TeleopUi ui(session, mirror, options, window);
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::microseconds(1'000'000 / 60);  // at most 60 frames per second
  for (long long n = 0; options.max_frames <= 0 || n < options.max_frames; ++n) {
    const auto start = clock::now();
    if (!ui.frame()) break;
    std::this_thread::sleep_until(start + period);
  }
  ui.report_saves();
}

}  // namespace rdsim
