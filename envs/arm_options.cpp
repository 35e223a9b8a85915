#include "rdsim/envs/arm_options.hpp"

#include <filesystem>

namespace rdsim {
namespace {

void resolve(std::string& path, const std::filesystem::path& folder) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return;
  path = std::filesystem::absolute(folder / path).lexically_normal().string();
}

}  // namespace

void resolve_arm_paths(ArmOptions& options, const std::string& folder) {
  const std::filesystem::path base = folder.empty() ? std::filesystem::path(".") : std::filesystem::path(folder);
  resolve(options.urdf, base);
  for (std::string& p : options.package_paths) resolve(p, base);
}

}  // namespace rdsim
