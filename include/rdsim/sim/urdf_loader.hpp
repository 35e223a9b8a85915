#pragma once
#include <string>

#include "rdsim/sim/robot_model.hpp"

// Reads URDF files (through urdfdom) into RobotModel. Only what rdsim can simulate is accepted:
// box/cylinder/sphere shapes, revolute/continuous/prismatic/fixed joints, one tree. Anything else
// (missing file, malformed XML, mesh geometry, floating/planar joints, several roots, a link
// with two parents) is an rdsim::Error whose message names the file and the problem.
namespace rdsim {

RobotModel load_urdf(const std::string& path);

// The same from XML text; `where` names it in messages (usually the file name).
RobotModel parse_urdf(const std::string& xml, const std::string& where);

}  // namespace rdsim
