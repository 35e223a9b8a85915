#include <string>

#include "backends.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

struct Backend {
  const char* name;
  std::unique_ptr<Renderer> (*make)(int width, int height);
};

// Preference order for "auto": the first one that works wins.
const Backend kBackends[] = {
#ifdef RDSIM_HAVE_EGL
    {"egl", render::make_egl_renderer},
#endif
    {"osmesa", render::make_osmesa_renderer},
};

constexpr int kMaxSide = 4096;

std::unique_ptr<Renderer> make_first_working(int width, int height) {
  std::string failures;
  for (const Backend& b : kBackends) {
    try {
      return b.make(width, height);
    } catch (const std::exception& e) {
      failures += (failures.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  throw Error("renderer: no backend works for \"auto\" (" + failures + ")");
}

}  // namespace

std::unique_ptr<Renderer> make_renderer(const std::string& backend, int width, int height) {
  if (width < 1 || width > kMaxSide || height < 1 || height > kMaxSide)
    throw Error("renderer: image size must be 1.." + std::to_string(kMaxSide) +
                " pixels per side, got " + std::to_string(width) + "x" + std::to_string(height));
  if (backend == "auto") return make_first_working(width, height);
  for (const Backend& b : kBackends)
    if (backend == b.name) return b.make(width, height);
  std::string known;
  for (const Backend& b : kBackends) known += (known.empty() ? "" : ", ") + std::string(b.name);
  throw Error("renderer: unknown backend \"" + backend + "\" (this build has: " + known +
              "; or \"auto\")");
}

std::vector<std::string> renderer_backends() {
  std::vector<std::string> names;
  for (const Backend& b : kBackends) names.emplace_back(b.name);
  return names;
}

}  // namespace rdsim
