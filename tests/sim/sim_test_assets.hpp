#pragma once
#include <cstdlib>
#include <string>

// Where the tests find rdsim's assets: $RDSIM_ROOT (set by ctest) or the source tree.
inline std::string test_asset(const std::string& relative) {
  const char* root = std::getenv("RDSIM_ROOT");
  return std::string(root && *root ? root : RDSIM_SOURCE_DIR) + "/assets/" + relative;
}
