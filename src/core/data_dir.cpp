#include "rdsim/core/data_dir.hpp"

#include <cstdlib>
#include <filesystem>

namespace rdsim {

namespace {

namespace fs = std::filesystem;

// The data an installed rdsim binary carries (rdsim/bin/rdsim beside rdsim/data); empty where the
// running program is not such a binary.
std::string installed_data_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path data = exe.parent_path().parent_path() / "data";
  return fs::is_directory(data / "assets", ec) ? data.string() : std::string();
}

}  // namespace

std::string repo_root() {
  if (const char* root = std::getenv("RDSIM_ROOT"); root && *root) return root;
  static const std::string found = [] {  // the program's files do not move while it runs
    std::error_code ec;
    if (fs::is_directory(fs::path(RDSIM_SOURCE_DIR) / "assets", ec)) return std::string(RDSIM_SOURCE_DIR);
    const std::string installed = installed_data_dir();
    return installed.empty() ? std::string(RDSIM_SOURCE_DIR) : installed;
  }();
  return found;
}

std::string shipped_file(const std::string& path) {
  std::error_code ec;
  const fs::path given(path);
  if (given.is_absolute() || fs::exists(given, ec)) return path;
  const fs::path shipped = fs::path(repo_root()) / given;
  return fs::exists(shipped, ec) ? shipped.string() : path;
}

}  // namespace rdsim
