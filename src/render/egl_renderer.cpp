// Off-screen rendering through EGL without any display or window: on a machine with a GPU driver
// that exposes EGL devices (NVIDIA, Mesa on a DRM render node) the frames are drawn by the GPU;
// elsewhere Mesa's surfaceless platform gives llvmpipe, the same rasteriser as the OSMesa backend.
// Only compiled when CMake finds EGL (RDSIM_HAVE_EGL).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "backends.hpp"
#include "gl_renderer.hpp"
#include "rdsim/core/assert.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim::render {
namespace {

GlProc egl_proc(const char* name) { return reinterpret_cast<GlProc>(eglGetProcAddress(name)); }

// Exact token match in a space-separated extension list (a plain strstr would match prefixes).
bool has_extension(const char* list, const std::string& name) {
  if (!list) return false;
  const std::string all = std::string(" ") + list + " ";
  return all.find(" " + name + " ") != std::string::npos;
}

// The display every EGL renderer of this process shares, chosen once. EGL displays are
// per-process singletons whose eglTerminate is not reference counted, so one renderer must never
// terminate it under another: it stays initialised until exit.
struct EglDisplayChoice {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLConfig config = nullptr;
  bool surfaceless = false;  // EGL_KHR_surfaceless_context: no pbuffer needed
  std::string failure;       // why no display is usable (when display == EGL_NO_DISPLAY)
};

struct Candidate {
  std::string name;  // for the error message
  EGLenum platform;
  void* native;
  bool maybe_software;  // may end up on llvmpipe
};

// A display that can make a desktop-GL context with a colour config; else EGL_NO_DISPLAY and
// the reason appended to `why`.
EglDisplayChoice try_display(PFNEGLGETPLATFORMDISPLAYEXTPROC get_display, const Candidate& c,
                             std::string& why) {
  auto fail = [&](EGLDisplay dpy, const std::string& what) {
    why += (why.empty() ? "" : "; ") + c.name + ": " + what;
    if (dpy != EGL_NO_DISPLAY) eglTerminate(dpy);
    return EglDisplayChoice{};
  };
  if (c.maybe_software) tune_process_for_software_rendering();
  EGLDisplay dpy = get_display(c.platform, c.native, nullptr);
  if (dpy == EGL_NO_DISPLAY) return fail(EGL_NO_DISPLAY, "no display");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor)) return fail(EGL_NO_DISPLAY, "eglInitialize failed");
  if (!eglBindAPI(EGL_OPENGL_API)) return fail(dpy, "no desktop OpenGL");
  // Colour and depth live in our framebuffer object, so the config only has to render desktop
  // GL; a pbuffer-capable one is needed only when surfaceless contexts are not supported.
  const bool surfaceless = has_extension(eglQueryString(dpy, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context");
  const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                            EGL_SURFACE_TYPE,    surfaceless ? 0 : EGL_PBUFFER_BIT,
                            EGL_RED_SIZE,        8,
                            EGL_GREEN_SIZE,      8,
                            EGL_BLUE_SIZE,       8,
                            EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!eglChooseConfig(dpy, attribs, &config, 1, &count) || count < 1)
    return fail(dpy, "no OpenGL config");
  // The drawer needs fixed-function GL: the default (version 1.0 requested) context is a
  // compatibility one on every implementation; probe that it can really be created.
  EGLContext probe = eglCreateContext(dpy, config, EGL_NO_CONTEXT, nullptr);
  if (probe == EGL_NO_CONTEXT) return fail(dpy, "eglCreateContext failed");
  eglDestroyContext(dpy, probe);
  return {dpy, config, surfaceless, ""};
}

// Hardware EGL devices first (NVIDIA GPUs appear only this way), then Mesa's surfaceless
// platform (llvmpipe when there is no GPU), then software devices.
EglDisplayChoice pick_display() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client) return {EGL_NO_DISPLAY, nullptr, false, "libEGL has no client extensions"};
  auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!has_extension(client, "EGL_EXT_platform_base") || !get_display)
    return {EGL_NO_DISPLAY, nullptr, false, "no EGL_EXT_platform_base"};

  std::vector<Candidate> hardware, software;
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (has_extension(client, "EGL_EXT_platform_device") && query_devices && device_string) {
    EGLDeviceEXT devices[16];
    EGLint n = 0;
    if (query_devices(16, devices, &n)) {
      for (EGLint i = 0; i < n; ++i) {
        const char* ext = device_string(devices[i], EGL_EXTENSIONS);
        const bool is_software = has_extension(ext, "EGL_MESA_device_software");
        const char* file = has_extension(ext, "EGL_EXT_device_drm")
                               ? device_string(devices[i], EGL_DRM_DEVICE_FILE_EXT)
                               : nullptr;
        std::string name = "device " + std::to_string(i);
        if (file) name += std::string(" (") + file + ")";
        (is_software ? software : hardware).push_back({name, EGL_PLATFORM_DEVICE_EXT, devices[i], is_software});
      }
    }
  }
  std::vector<Candidate> order = hardware;
  if (has_extension(client, "EGL_MESA_platform_surfaceless"))
    order.push_back({"surfaceless", EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, true});
  order.insert(order.end(), software.begin(), software.end());
  if (order.empty()) return {EGL_NO_DISPLAY, nullptr, false, "no EGL device and no surfaceless platform"};

  std::string why;
  for (const Candidate& c : order) {
    EglDisplayChoice choice = try_display(get_display, c, why);
    if (choice.display != EGL_NO_DISPLAY) return choice;
  }
  return {EGL_NO_DISPLAY, nullptr, false, why};
}

const EglDisplayChoice& shared_display() {
  static const EglDisplayChoice choice = pick_display();
  return choice;
}

// Framebuffer-object entry points: GL 3.0 / ARB_framebuffer_object names, or the EXT ones with
// the same enums. GLVND hands out a stub for any gl* name, so the GL version and extension
// string decide which names are real.
struct FboApi {
  PFNGLGENFRAMEBUFFERSPROC gen_framebuffers = nullptr;
  PFNGLBINDFRAMEBUFFERPROC bind_framebuffer = nullptr;
  PFNGLGENRENDERBUFFERSPROC gen_renderbuffers = nullptr;
  PFNGLBINDRENDERBUFFERPROC bind_renderbuffer = nullptr;
  PFNGLRENDERBUFFERSTORAGEPROC renderbuffer_storage = nullptr;
  PFNGLFRAMEBUFFERRENDERBUFFERPROC framebuffer_renderbuffer = nullptr;
  PFNGLCHECKFRAMEBUFFERSTATUSPROC check_framebuffer_status = nullptr;
};

template <typename Fn>
void load_fbo(Fn& slot, const std::string& name) {
  slot = reinterpret_cast<Fn>(egl_proc(name.c_str()));
  if (!slot) throw Error("GL function " + name + " not available");
}

FboApi load_fbo_api(const GlApi& gl) {
  const char* version = reinterpret_cast<const char*>(gl.glGetString(GL_VERSION));
  const char* extensions = reinterpret_cast<const char*>(gl.glGetString(GL_EXTENSIONS));
  std::string suffix;
  if (!(version && std::atoi(version) >= 3) && !has_extension(extensions, "GL_ARB_framebuffer_object")) {
    if (!has_extension(extensions, "GL_EXT_framebuffer_object"))
      throw Error(std::string("the GL context (") + (version ? version : "?") + ") has no framebuffer objects");
    suffix = "EXT";
  }
  FboApi f;
  load_fbo(f.gen_framebuffers, "glGenFramebuffers" + suffix);
  load_fbo(f.bind_framebuffer, "glBindFramebuffer" + suffix);
  load_fbo(f.gen_renderbuffers, "glGenRenderbuffers" + suffix);
  load_fbo(f.bind_renderbuffer, "glBindRenderbuffer" + suffix);
  load_fbo(f.renderbuffer_storage, "glRenderbufferStorage" + suffix);
  load_fbo(f.framebuffer_renderbuffer, "glFramebufferRenderbuffer" + suffix);
  load_fbo(f.check_framebuffer_status, "glCheckFramebufferStatus" + suffix);
  return f;
}

// Colour RGBA8 + 24-bit depth, like the OSMesa backend's buffers, so both rasterise alike. The
// objects die with the context, which nothing shares.
void create_framebuffer(const GlApi& gl, const FboApi& f, int width, int height) {
  GLuint fbo = 0, buffers[2] = {0, 0};
  f.gen_framebuffers(1, &fbo);
  f.bind_framebuffer(GL_FRAMEBUFFER, fbo);
  f.gen_renderbuffers(2, buffers);
  f.bind_renderbuffer(GL_RENDERBUFFER, buffers[0]);
  f.renderbuffer_storage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  f.framebuffer_renderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
  f.bind_renderbuffer(GL_RENDERBUFFER, buffers[1]);
  f.renderbuffer_storage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  f.framebuffer_renderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffers[1]);
  const GLenum status = f.check_framebuffer_status(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE || gl.glGetError() != GL_NO_ERROR)
    throw Error("framebuffer object incomplete (status " + std::to_string(status) + ")");
}

class EglRenderer final : public GlRenderer {
public:
  // rdsim::Error saying what failed when this device cannot give the drawer a context.
  EglRenderer(const EglDisplayChoice& d, int width, int height) : GlRenderer(width, height), display_(d.display) {
    // The bound API is per thread: set it again in case another thread picked the display.
    if (!eglBindAPI(EGL_OPENGL_API)) throw Error("eglBindAPI failed");
    context_ = eglCreateContext(display_, d.config, EGL_NO_CONTEXT, nullptr);
    if (context_ == EGL_NO_CONTEXT) throw Error("eglCreateContext failed");
    if (!d.surfaceless) {
      const EGLint attribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
      surface_ = eglCreatePbufferSurface(display_, d.config, attribs);
      if (surface_ == EGL_NO_SURFACE) {
        release();
        throw Error("eglCreatePbufferSurface failed");
      }
    }
    // Our framebuffer object stays bound in our context: every frame is drawn into it.
    start(egl_proc, [this] { create_framebuffer(gl(), load_fbo_api(gl()), width_, height_); });
  }
  ~EglRenderer() override { release(); }

  std::string backend() const override { return "egl"; }

private:
  // EGL only knows about EGL contexts: an OSMesa renderer binds its context in Mesa's GL dispatch
  // (libglapi), which Mesa's EGL driver shares, behind GLVND's back, so eglGetCurrentContext()
  // still names ours. What OSMesa reports as current right after our bind tells us whether that
  // happened since (on a non-Mesa driver it stays unchanged unless OSMesa really binds).
  void make_current() override {
    const bool ours = eglGetCurrentContext() == context_;
    if (ours && OSMesaGetCurrentContext() == osmesa_view_) return;
    // EGL ignores a bind of the context it already thinks is current: release it first.
    if (ours) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (!eglMakeCurrent(display_, surface_, surface_, context_)) {
      const EGLint error = eglGetError();
      // Unlike OSMesa, an EGL context stays bound to the thread that last drew with it: drawing
      // from another thread breaks the Renderer's contract (renderer.hpp), a bug in the caller.
      RDSIM_ASSERT(error != EGL_BAD_ACCESS, "egl renderer: its context is current in another thread (an egl "
                                            "Renderer must keep drawing from the thread it last drew from)");
      throw Error("egl renderer: eglMakeCurrent failed (error 0x" + hex(error) + ")");
    }
    osmesa_view_ = OSMesaGetCurrentContext();
  }

  void unbind() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }

  void release() override {
    if (eglGetCurrentContext() == context_)
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  }

  static std::string hex(EGLint v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%X", static_cast<unsigned>(v));
    return buf;
  }

  EGLDisplay display_;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;  // a 1x1 pbuffer only without surfaceless contexts
  OSMesaContext osmesa_view_ = nullptr;  // OSMesaGetCurrentContext() just after our last bind
};

}  // namespace

std::unique_ptr<Renderer> make_egl_renderer(int width, int height) {
  const EglDisplayChoice& d = shared_display();
  if (d.display == EGL_NO_DISPLAY) throw Error("egl renderer: no usable EGL device (" + d.failure + ")");
  try {
    return std::make_unique<EglRenderer>(d, width, height);
  } catch (const Error& e) {  // no context, or one without what the drawer needs
    throw Error(std::string("egl renderer: no usable EGL device (") + e.what() + ")");
  }
}

}  // namespace rdsim::render
