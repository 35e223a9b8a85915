#pragma once
#include <string>
#include <vector>

// `rdsim urdf FILE`: what a user needs to write a reach config for their robot without reading
// the XML: the tree of links and joints with types and limits, the effector candidates and a
// config skeleton (src/app/urdf.cpp).
namespace rdsim {

struct UrdfOptions {
  std::string path;                        // the URDF file
  std::vector<std::string> package_paths;  // folders for package:// meshes (env.package_paths)
};
int urdf_command(const UrdfOptions& options);

}  // namespace rdsim
