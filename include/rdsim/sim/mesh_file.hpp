#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include "rdsim/core/triangle_mesh.hpp"
#include "rdsim/sim/robot_model.hpp"

// Mesh files of URDF <mesh> elements: STL (binary and ASCII), Wavefront OBJ (with its .mtl) and
// COLLADA DAE, read with Assimp. Positions come out in metres in the element's frame:
//  - a DAE's <unit meter="..."> is applied, and its <up_axis> turned into URDF's z-up (a Y_UP file's
//    +y becomes +z; Z_UP files are taken as they are, as ROS tools do);
//  - STL and OBJ carry no unit: their numbers are metres;
//  - then the URDF's scale (x, y, z; a negative factor mirrors, and the winding is kept outward).
// Normals are recomputed (smooth across edges under 45 degrees, sharp above); file colours are the
// materials' diffuse colours (textures are not read).
//
// Files are read under rdsim's rule for input files (rdsim/core/input_file.hpp: regular files
// only, opened without blocking), the mesh and the files it names (an OBJ's .mtl) together at most
// max_mesh_bytes; Assimp parses them from memory. Limits, each an rdsim::Error "<file>: <reason>":
// a file over max_mesh_bytes is refused unread; more than max_mesh_triangles (counted before any
// processing), no triangles, coordinates that are not finite or beyond max_mesh_extent, or
// anything Assimp cannot read.
namespace rdsim {

inline constexpr std::uint64_t max_mesh_bytes = 32ull * 1024 * 1024;  // 32 MiB
inline constexpr std::size_t max_mesh_triangles = 500'000;            // per file, after instancing
inline constexpr double max_mesh_extent = 1000.0;                     // m: |coordinate| after scaling
// A convex hull with more vertices than this is reduced (Bullet's btShapeHull: the hull's support
// points in 42 fixed directions, at most 42 vertices) so that a moving link's collision test stays cheap.
inline constexpr std::size_t max_hull_points = 100;

enum class MeshFormat { Stl, Obj, Dae };
// The format a file's extension names (case-insensitive); an rdsim::Error for any other.
MeshFormat mesh_format(const std::string& file);

// Reads and converts one file, uncached. `scale` must be finite and non-zero in x, y and z.
TriangleMesh read_mesh_file(const std::string& file, const Eigen::Vector3d& scale);

// The convex hull of a mesh's positions (exact up to max_hull_points vertices, reduced above).
ConvexHull convex_hull(const TriangleMesh& mesh);

// The same through a process-wide cache, one entry per (file, its size and modification time,
// scale): N envs loading the same URDF read each mesh once and share it. Thread-safe; a thread
// asking for a mesh another thread is reading waits for it. Entries stay for the process's life
// (failures are not cached: a fixed file is read again).
std::shared_ptr<const TriangleMesh> load_mesh(const std::string& file, const Eigen::Vector3d& scale);
std::shared_ptr<const ConvexHull> load_convex_hull(const std::string& file, const Eigen::Vector3d& scale);

}  // namespace rdsim
