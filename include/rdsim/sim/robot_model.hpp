#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rdsim/core/triangle_mesh.hpp"

// A robot (or any URDF object) as plain immutable data: what the file says, nothing simulated.
// The simulation state lives elsewhere (PhysicsWorld, Robot), MuJoCo's model/data split.
// Units: metres, kilograms, radians, seconds, newtons (N·m for revolute efforts).
namespace rdsim {

enum class ShapeType { Box, Cylinder, Sphere, Mesh };

// The convex hull of a collision mesh: what a moving link collides with (src/sim/mesh_file.hpp).
struct ConvexHull {
  std::vector<Eigen::Vector3f> points;  // metres, in the mesh's frame; at most max_hull_points
  double volume = 0.0;                  // m^3, of the hull through `points`
};

// A mesh element: the file as the URDF names it, the file it resolved to, and its triangles with
// the scale applied. Loaded meshes are shared between models (one copy per file and scale).
struct MeshGeometry {
  std::string uri;   // as written in the URDF ("package://panda/meshes/link1.obj")
  std::string file;  // the file read
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const ConvexHull> hull;  // <collision> elements only; null for <visual>
};

// A shape placed in its link's frame. Cylinders run along their local z axis.
struct Shape {
  ShapeType type = ShapeType::Box;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // box: full extents along x, y, z
  double radius = 0.0;                             // cylinder, sphere
  double length = 0.0;                             // cylinder
  MeshGeometry mesh;                               // mesh
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
};

// Kept for a renderer; the physics never reads it.
struct VisualShape {
  Shape shape;
  Eigen::Vector4f rgba{0.7f, 0.7f, 0.7f, 1.0f};
  std::string material;  // the URDF material name, "" when none
};

struct Inertial {
  double mass = 0.0;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();        // about the centre of mass, in `origin`'s axes
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // centre-of-mass frame in the link frame
};

struct Link {
  std::string name;
  Inertial inertial;
  std::vector<Shape> collisions;
  std::vector<VisualShape> visuals;
  int parent_joint = -1;  // index into RobotModel::joints; -1 for the root
};

enum class JointType { Revolute, Continuous, Prismatic, Fixed };

struct Joint {
  std::string name;
  JointType type = JointType::Fixed;
  int parent_link = -1;
  int child_link = -1;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // child frame in the parent frame at q = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           // unit vector in the child (= joint) frame
  // Position limits; continuous joints have -inf/+inf, fixed joints 0/0.
  double lower = 0.0, upper = 0.0;
  double effort = 0.0;    // largest force/torque the actuator gives
  double velocity = 0.0;  // largest speed (rad/s or m/s)
  double damping = 0.0, friction = 0.0;

  bool movable() const { return type != JointType::Fixed; }
};

struct RobotModel {
  std::string name;
  std::string source;  // the file it was read from, for messages
  // Tree order: links[0] is the root and every parent comes before its children. The joint
  // above link i (i >= 1) is joints[i - 1], so joints are in tree order too.
  std::vector<Link> links;
  std::vector<Joint> joints;

  int link_index(std::string_view link_name) const;    // -1 when absent
  int joint_index(std::string_view joint_name) const;  // -1 when absent
  // Like link_index, but rdsim::Error naming the model's file when absent.
  int require_link(std::string_view link_name) const;
  int movable_joint_count() const;
  double total_mass() const;
  // Every link's frame relative to the root at q = 0 (all joints at their zero position).
  std::vector<Eigen::Isometry3d> link_poses_at_zero() const;
};

}  // namespace rdsim
