#include "rdsim/sim/urdf_loader.hpp"

#include <console_bridge/console.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <urdf_parser/urdf_parser.h>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace rdsim {
namespace {

// urdfdom reports why it rejected a file only through console_bridge; we collect those lines so
// the rdsim::Error can say it instead of leaving the reason in a log the user may not see.
class MessageCollector : public console_bridge::OutputHandler {
public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    if (!messages.empty()) messages += "; ";
    messages += text;
  }
  std::string messages;
};

std::mutex& parser_mutex() {  // console_bridge's handler is process-wide
  static std::mutex m;
  return m;
}

urdf::ModelInterfaceSharedPtr parse_with_messages(const std::string& xml, const std::string& where) {
  std::lock_guard<std::mutex> lock(parser_mutex());
  MessageCollector collector;
  console_bridge::useOutputHandler(&collector);
  urdf::ModelInterfaceSharedPtr model;
  std::string thrown;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    thrown = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    std::string why = !thrown.empty() ? thrown : collector.messages;
    if (why.empty()) why = "urdfdom rejected it without a reason";
    throw Error(where + ": not a valid URDF: " + why);
  }
  return model;
}

Eigen::Isometry3d to_isometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  return t;
}

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw Error(where + ": " + what); }

Shape to_shape(const urdf::GeometrySharedPtr& g, const urdf::Pose& origin, const std::string& where,
               const std::string& link) {
  const std::string ctx = "link \"" + link + "\": ";
  if (!g) fail(where, ctx + "a collision/visual element has no <geometry>");
  Shape s;
  s.origin = to_isometry(origin);
  switch (g->type) {
    case urdf::Geometry::BOX: {
      const auto& d = std::static_pointer_cast<urdf::Box>(g)->dim;
      s.type = ShapeType::Box;
      s.size = Eigen::Vector3d(d.x, d.y, d.z);
      if (!(s.size.minCoeff() > 0.0)) fail(where, ctx + "box size must be positive in x, y and z");
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto c = std::static_pointer_cast<urdf::Cylinder>(g);
      s.type = ShapeType::Cylinder;
      s.radius = c->radius;
      s.length = c->length;
      if (!(s.radius > 0.0 && s.length > 0.0)) fail(where, ctx + "cylinder radius and length must be positive");
      break;
    }
    case urdf::Geometry::SPHERE:
      s.type = ShapeType::Sphere;
      s.radius = std::static_pointer_cast<urdf::Sphere>(g)->radius;
      if (!(s.radius > 0.0)) fail(where, ctx + "sphere radius must be positive");
      break;
    case urdf::Geometry::MESH:
      fail(where, ctx + "mesh geometry (\"" + std::static_pointer_cast<urdf::Mesh>(g)->filename +
                      "\") is not supported; rdsim uses primitive shapes only (box, cylinder, sphere)");
    default:
      fail(where, ctx + "unknown geometry type");
  }
  return s;
}

Link to_link(const urdf::Link& in, const std::string& where) {
  Link out;
  out.name = in.name;
  if (in.inertial) {
    const urdf::Inertial& i = *in.inertial;
    if (!(i.mass >= 0.0) || !std::isfinite(i.mass))
      fail(where, "link \"" + in.name + "\": mass must be >= 0");
    out.inertial.mass = i.mass;
    out.inertial.origin = to_isometry(i.origin);
    out.inertial.inertia << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
    if (!(i.ixx >= 0.0 && i.iyy >= 0.0 && i.izz >= 0.0) || !out.inertial.inertia.allFinite())
      fail(where, "link \"" + in.name + "\": inertia ixx, iyy, izz must be finite and >= 0");
  }
  for (const auto& c : in.collision_array) out.collisions.push_back(to_shape(c->geometry, c->origin, where, in.name));
  for (const auto& v : in.visual_array) {
    VisualShape vs;
    vs.shape = to_shape(v->geometry, v->origin, where, in.name);
    if (v->material) {
      const urdf::Color& c = v->material->color;
      vs.rgba = Eigen::Vector4f(c.r, c.g, c.b, c.a);
      vs.material = v->material->name;
    }
    out.visuals.push_back(vs);
  }
  return out;
}

Joint to_joint(const urdf::Joint& in, const std::string& where) {
  Joint j;
  j.name = in.name;
  const std::string ctx = "joint \"" + in.name + "\": ";
  switch (in.type) {
    case urdf::Joint::REVOLUTE: j.type = JointType::Revolute; break;
    case urdf::Joint::CONTINUOUS: j.type = JointType::Continuous; break;
    case urdf::Joint::PRISMATIC: j.type = JointType::Prismatic; break;
    case urdf::Joint::FIXED: j.type = JointType::Fixed; break;
    case urdf::Joint::FLOATING: fail(where, ctx + "floating joints are not supported");
    case urdf::Joint::PLANAR: fail(where, ctx + "planar joints are not supported");
    default: fail(where, ctx + "unknown joint type");
  }
  j.origin = to_isometry(in.parent_to_joint_origin_transform);
  if (j.movable()) {
    const Eigen::Vector3d axis(in.axis.x, in.axis.y, in.axis.z);
    if (!(axis.norm() > 1e-9)) fail(where, ctx + "<axis> must not be zero");
    j.axis = axis.normalized();
    if (!in.limits) fail(where, ctx + "a movable joint needs <limit effort=... velocity=...>");
    j.effort = in.limits->effort;
    j.velocity = in.limits->velocity;
    if (!(j.effort > 0.0)) fail(where, ctx + "<limit effort> must be > 0");
    if (!(j.velocity > 0.0)) fail(where, ctx + "<limit velocity> must be > 0");
  }
  if (j.type == JointType::Continuous) {
    j.lower = -std::numeric_limits<double>::infinity();
    j.upper = std::numeric_limits<double>::infinity();
  } else if (j.type != JointType::Fixed) {
    j.lower = in.limits->lower;
    j.upper = in.limits->upper;
    if (!(j.lower <= j.upper)) fail(where, ctx + "<limit lower> must not exceed upper");
  }
  if (in.dynamics) {
    j.damping = in.dynamics->damping;
    j.friction = in.dynamics->friction;
  }
  return j;
}

// urdfdom keeps joints in a name-sorted map; users expect joints numbered in file order (as
// PyBullet does), so we find where each joint's tag starts in the text.
std::map<std::string, size_t> joint_file_positions(const std::string& xml) {
  std::map<std::string, size_t> pos;
  for (size_t at = xml.find("<joint"); at != std::string::npos; at = xml.find("<joint", at + 1)) {
    const size_t end = xml.find('>', at);
    const size_t name = xml.find("name", at);
    if (end == std::string::npos || name == std::string::npos || name > end) continue;
    const size_t q1 = xml.find_first_of("\"'", name);
    if (q1 == std::string::npos || q1 > end) continue;
    const size_t q2 = xml.find(xml[q1], q1 + 1);
    if (q2 == std::string::npos) continue;
    pos.emplace(xml.substr(q1 + 1, q2 - q1 - 1), at);  // first occurrence wins (<transmission> comes later)
  }
  return pos;
}

}  // namespace

RobotModel parse_urdf(const std::string& xml, const std::string& where) {
  const urdf::ModelInterfaceSharedPtr in = parse_with_messages(xml, where);
  const auto file_pos = joint_file_positions(xml);

  // urdfdom lets a later joint silently replace an earlier parent of the same link.
  std::map<std::string, std::string> parent_of;
  for (const auto& [name, joint] : in->joints_) {
    auto [it, fresh] = parent_of.emplace(joint->child_link_name, name);
    if (!fresh)
      fail(where, "link \"" + joint->child_link_name + "\" has two parent joints (\"" + it->second + "\" and \"" +
                      name + "\"); a URDF must be a tree");
  }

  RobotModel model;
  model.name = in->getName();
  model.source = where;
  const urdf::LinkConstSharedPtr root = in->getRoot();
  if (!root) fail(where, "no root link");

  // Depth-first from the root, children in file order; the explicit stack keeps deep chains safe.
  std::vector<std::pair<urdf::LinkConstSharedPtr, int>> stack{{root, -1}};  // link, joint above it
  while (!stack.empty()) {
    auto [link, joint_index] = stack.back();
    stack.pop_back();
    const int link_index = static_cast<int>(model.links.size());
    model.links.push_back(to_link(*link, where));
    model.links.back().parent_joint = joint_index;
    if (joint_index >= 0) model.joints[static_cast<size_t>(joint_index)].child_link = link_index;

    std::vector<urdf::JointSharedPtr> children = link->child_joints;
    std::sort(children.begin(), children.end(), [&](const auto& a, const auto& b) {
      const auto pa = file_pos.find(a->name), pb = file_pos.find(b->name);
      const size_t ia = pa == file_pos.end() ? SIZE_MAX : pa->second;
      const size_t ib = pb == file_pos.end() ? SIZE_MAX : pb->second;
      return ia != ib ? ia > ib : a->name > b->name;  // reversed: the stack pops the first child first
    });
    for (const auto& cj : children) {
      Joint j = to_joint(*cj, where);
      j.parent_link = link_index;
      const urdf::LinkConstSharedPtr child = in->getLink(cj->child_link_name);
      if (!child) fail(where, "joint \"" + cj->name + "\": child link \"" + cj->child_link_name + "\" not found");
      stack.emplace_back(child, -1);
      // The joint's index must be the child's index - 1; the child gets its index when popped,
      // so joints are appended then and reordered below.
      model.joints.push_back(j);
      stack.back().second = static_cast<int>(model.joints.size()) - 1;
    }
  }
  if (model.links.size() != in->links_.size())
    fail(where, "some links are not connected to the root link \"" + root->name + "\" (a loop or a second tree)");

  // Joints were appended in discovery order; put them in child-link order (joints[i] above links[i+1]).
  std::vector<Joint> ordered(model.joints.size());
  for (size_t li = 1; li < model.links.size(); ++li) {
    const int ji = model.links[li].parent_joint;
    ordered[li - 1] = model.joints[static_cast<size_t>(ji)];
    model.links[li].parent_joint = static_cast<int>(li) - 1;
  }
  model.joints = std::move(ordered);
  return model;
}

RobotModel load_urdf(const std::string& path) {
  return parse_urdf(read_file(path), path);
}

}  // namespace rdsim
