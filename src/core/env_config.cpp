#include "rdsim/core/env_config.hpp"

#include <cstdlib>

namespace rdsim {

const char* to_string(ObservationMode mode) {
  return mode == ObservationMode::RawPixels ? "raw_pixels" : "ground_truth";
}

const char* to_string(RenderMode mode) { return mode == RenderMode::RgbArray ? "rgb_array" : "none"; }

std::string repo_root() {
  if (const char* root = std::getenv("RDSIM_ROOT"); root && *root) return root;
  return RDSIM_SOURCE_DIR;
}

std::string asset_root(const EnvConfig& config) {
  if (!config.urdf_root.empty()) return config.urdf_root;
  return repo_root() + "/assets";
}

}  // namespace rdsim
