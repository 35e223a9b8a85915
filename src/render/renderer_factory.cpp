#include <string>

#include "backends.hpp"
#include "rdsim/error.hpp"

namespace rdsim {
namespace {

struct Backend {
  const char* name;
  std::unique_ptr<Renderer> (*make)(int width, int height);
};

const Backend kBackends[] = {
    {"osmesa", render::make_osmesa_renderer},
};

constexpr int kMaxSide = 4096;

}  // namespace

std::unique_ptr<Renderer> make_renderer(const std::string& backend, int width, int height) {
  if (width < 1 || width > kMaxSide || height < 1 || height > kMaxSide)
    throw Error("renderer: image size must be 1.." + std::to_string(kMaxSide) +
                " pixels per side, got " + std::to_string(width) + "x" + std::to_string(height));
  for (const Backend& b : kBackends)
    if (backend == b.name) return b.make(width, height);
  std::string known;
  for (const Backend& b : kBackends) known += (known.empty() ? "" : ", ") + std::string(b.name);
  throw Error("renderer: unknown backend \"" + backend + "\" (this build has: " + known + ")");
}

std::vector<std::string> renderer_backends() {
  std::vector<std::string> names;
  for (const Backend& b : kBackends) names.emplace_back(b.name);
  return names;
}

}  // namespace rdsim
