#pragma once
#include <cstdint>
#include <string>

#include "rdsim/sim/robot_model.hpp"

// Reads URDF files (through urdfdom) into RobotModel. Only what rdsim can simulate is accepted:
// box/cylinder/sphere shapes, revolute/continuous/prismatic/fixed joints, one tree. Anything else
// (missing file, malformed XML, mesh geometry, floating/planar joints, several roots, a link
// with two parents) is an rdsim::Error whose message names the file and the problem.
//
// Physics is checked too, each failure naming the file, the link or joint and the value: masses
// finite, >= 0, > 0 on every link of a movable joint; inertias finite, positive definite,
// obeying the triangle inequality and plausible for the mass; joint limits, efforts, speeds,
// origins, axes and shape sizes finite. Files above max_urdf_bytes are refused unread.
namespace rdsim {

inline constexpr std::uint64_t max_urdf_bytes = 16ull * 1024 * 1024;  // 16 MiB

RobotModel load_urdf(const std::string& path);

// The same from XML text; `where` names it in messages (usually the file name).
RobotModel parse_urdf(const std::string& xml, const std::string& where);

}  // namespace rdsim
