#pragma once
// Where a URDF <mesh filename="..."> lies on disk (the rules are in rdsim/sim/urdf_loader.hpp).
#include <string>
#include <vector>

namespace rdsim {

// The first existing file among the candidates for `uri`; rdsim::Error "file not found (searched:
// ...)" listing them all when none exists, or naming an unsupported URI scheme.
std::string resolve_mesh_path(const std::string& uri, const std::string& urdf_file,
                              const std::vector<std::string>& search_path);

}  // namespace rdsim
