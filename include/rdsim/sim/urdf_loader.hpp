#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rdsim/sim/robot_model.hpp"

// Reads URDF files (through urdfdom) into RobotModel. Only what rdsim can simulate is accepted:
// box/cylinder/sphere/mesh shapes, revolute/continuous/prismatic/fixed joints, one tree. Anything
// else (missing file, malformed XML, floating/planar joints, several roots, a link with two
// parents) is an rdsim::Error whose message names the file and the problem.
//
// Physics is checked too, each failure naming the file, the link or joint and the value: masses
// finite, >= 0, > 0 on every link of a movable joint; inertias finite, positive definite,
// obeying the triangle inequality and plausible for the mass; joint limits, efforts, speeds,
// origins, axes and shape sizes finite. Files above max_urdf_bytes are refused unread.
//
// Meshes (<mesh filename="..." scale="x y z"/>, STL, OBJ or DAE; reading, units and limits in
// rdsim/sim/mesh_file.hpp) are read while the URDF loads, through the process-wide mesh cache.
// Where the file is looked for, the first that exists winning:
//  - "package://NAME/REST": DIR/NAME/REST for each DIR of options.search_path in order; then
//    FOLDER/REST where FOLDER is the URDF's own folder or the nearest folder above it named NAME
//    (a ROS package laid out as NAME/urdf/robot.urdf and NAME/meshes/...); then
//    URDF_FOLDER/NAME/REST (how pybullet reads package://, e.g. pybullet_data's Panda);
//  - "file:///abs/path" and absolute paths: that file;
//  - a relative path: URDF_FOLDER/path, then DIR/path for each DIR of options.search_path.
// A mesh that is missing, unreadable, malformed or over a limit is one rdsim::Error naming the
// URDF, the link and the mesh, e.g.
//   panda.urdf: link "panda_link3": mesh "package://meshes/link3.obj": file not found (searched: ...)
// Collision meshes get their convex hull too (the physics' shape for moving links).
namespace rdsim {

inline constexpr std::uint64_t max_urdf_bytes = 16ull * 1024 * 1024;  // 16 MiB

struct UrdfLoadOptions {
  // Folders searched for package:// and relative mesh paths (see above), in order.
  std::vector<std::string> search_path;
};

RobotModel load_urdf(const std::string& path, const UrdfLoadOptions& options = {});

// The same from XML text; `where` names it in messages (usually the file name) and its folder is
// the URDF folder of relative mesh paths.
RobotModel parse_urdf(const std::string& xml, const std::string& where, const UrdfLoadOptions& options = {});

}  // namespace rdsim
