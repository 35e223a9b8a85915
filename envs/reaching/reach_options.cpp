#include "rdsim/envs/reaching/reach_options.hpp"

#include <utility>

#include "rdsim/core/data_dir.hpp"
#include "rdsim/envs/randomization.hpp"

namespace rdsim {

std::string asset_root(const ReachOptions& options) {
  if (!options.urdf_root.empty()) return options.urdf_root;
  return repo_root() + "/assets";
}

EnvConfig reach_env_config(EnvConfig common, ReachOptions options) {
  common.options = {EnvOptions(std::move(options)), EnvOptions(RandomizeOptions{})};
  return common;
}

}  // namespace rdsim
