#include "rdsim/envs/arm_options.hpp"

#include "rdsim/core/config_path.hpp"

namespace rdsim {

void resolve_arm_paths(ArmOptions& options, const std::string& folder) {
  options.urdf = path_from(folder, options.urdf);
  for (std::string& p : options.package_paths) p = path_from(folder, p);
}

}  // namespace rdsim
