#pragma once
// Shared by the mesh tests: the hand-made fixtures (tests/sim/meshes) and pybullet_data's robots.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <string>

#include "rdsim/core/triangle_mesh.hpp"

// tests/sim/meshes/<name>, under $RDSIM_ROOT (set by ctest) or the source tree.
inline std::string mesh_fixture(const std::string& name) {
  const char* root = std::getenv("RDSIM_ROOT");
  return std::string(root && *root ? root : RDSIM_SOURCE_DIR) + "/tests/sim/meshes/" + name;
}

// pybullet_data's folder in the installed pybullet package (found by CMake through
// RDSIM_VENV_PYTHON), or "" with a warning saying why the case is skipped.
inline std::string pybullet_data() {
  const std::string dir = RDSIM_PYBULLET_DATA;
  if (dir.empty())
    WARN("skipped: pybullet_data not found (CMake ran `RDSIM_VENV_PYTHON -c \"import pybullet_data\"` and it failed; "
         "run tools/setup.sh or pass -DRDSIM_VENV_PYTHON=<a python with pybullet>)");
  return dir;
}

// Signed volume enclosed by a closed mesh (positive when its triangles wind outward), m^3.
inline double enclosed_volume(const rdsim::TriangleMesh& m) {
  double six = 0.0;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const Eigen::Vector3d a = m.positions[m.indices[t]].cast<double>();
    const Eigen::Vector3d b = m.positions[m.indices[t + 1]].cast<double>();
    const Eigen::Vector3d c = m.positions[m.indices[t + 2]].cast<double>();
    six += a.dot(b.cross(c));
  }
  return six / 6.0;
}
