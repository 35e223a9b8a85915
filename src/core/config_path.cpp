#include "rdsim/core/config_path.hpp"

#include <filesystem>

namespace rdsim {

std::string path_from(const std::string& folder, const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return path;
  const fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  std::error_code ec;
  const fs::path whole = fs::absolute((folder.empty() ? fs::path(".") : fs::path(folder)) / p, ec);
  return ec ? path : whole.lexically_normal().string();
}

}  // namespace rdsim
