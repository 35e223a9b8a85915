#include "mesh_path.hpp"

#include <filesystem>
#include <system_error>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

namespace fs = std::filesystem;

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Candidates for package://name/rest: <dir>/name/rest for each search dir; then the URDF's own
// folder or the nearest folder above it that is named `name` (a ROS description package:
// name/urdf/robot.urdf beside name/meshes/); then <URDF folder>/name/rest (pybullet's reading:
// the scheme dropped, the rest relative to the URDF).
std::vector<fs::path> package_candidates(const std::string& rest_of_uri, const fs::path& urdf_dir,
                                         const std::vector<std::string>& search_path) {
  const std::size_t slash = rest_of_uri.find('/');
  const std::string name = rest_of_uri.substr(0, slash);
  const std::string rest = slash == std::string::npos ? "" : rest_of_uri.substr(slash + 1);
  if (name.empty() || rest.empty()) throw Error("a package:// URI needs a package name and a file (package://name/path)");
  std::vector<fs::path> out;
  for (const std::string& dir : search_path) out.push_back(fs::path(dir) / name / rest);
  std::error_code ec;
  for (fs::path dir = fs::absolute(urdf_dir, ec); !ec && !dir.empty(); dir = dir.parent_path()) {
    if (dir.filename() == name) {
      out.push_back(dir / rest);
      break;
    }
    if (dir == dir.parent_path()) break;
  }
  out.push_back(urdf_dir / name / rest);
  return out;
}

}  // namespace

std::string resolve_mesh_path(const std::string& uri, const std::string& urdf_file,
                              const std::vector<std::string>& search_path) {
  if (uri.empty()) throw Error("empty filename");
  fs::path urdf_dir = fs::path(urdf_file).parent_path();
  if (urdf_dir.empty()) urdf_dir = ".";
  std::vector<fs::path> candidates;
  if (starts_with(uri, "package://")) {
    candidates = package_candidates(uri.substr(10), urdf_dir, search_path);
  } else {
    const std::string path = starts_with(uri, "file://") ? uri.substr(7) : uri;
    if (path.find("://") != std::string::npos)
      throw Error("unsupported URI scheme (rdsim reads package://, file:// and plain paths)");
    if (fs::path(path).is_absolute()) {
      candidates.push_back(path);
    } else {
      candidates.push_back(urdf_dir / path);
      for (const std::string& dir : search_path) candidates.push_back(fs::path(dir) / path);
    }
  }
  std::string searched;
  for (const fs::path& c : candidates) {
    std::error_code ec;
    if (fs::exists(c, ec)) return c.lexically_normal().string();
    searched += (searched.empty() ? "" : ", ") + c.lexically_normal().string();
  }
  throw Error("file not found (searched: " + searched + ")");
}

}  // namespace rdsim
