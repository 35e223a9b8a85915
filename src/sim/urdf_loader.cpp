#include "rdsim/sim/urdf_loader.hpp"

#include <console_bridge/console.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <urdf_parser/urdf_parser.h>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/sim/mesh_file.hpp"
#include "mesh_path.hpp"

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

// XML elements nested deeper than this are refused before urdfdom sees them: its parser takes
// time quadratic in the depth (30,000 levels: over half a minute). A URDF needs about six.
constexpr int kMaxXmlDepth = 100;

void check_xml_depth(const std::string& xml, const std::string& where) {
  int depth = 0;
  for (std::size_t at = xml.find('<'); at != std::string::npos; at = xml.find('<', at + 1)) {
    if (xml.compare(at, 4, "<!--") == 0) {  // comment: skip to its end
      at = xml.find("-->", at + 4);
      if (at == std::string::npos) return;  // unterminated: urdfdom reports it
      continue;
    }
    if (at + 1 < xml.size() && (xml[at + 1] == '!' || xml[at + 1] == '?')) continue;  // declarations
    const bool closing = at + 1 < xml.size() && xml[at + 1] == '/';
    // The tag's end, outside quoted attribute values.
    std::size_t end = at + 1;
    for (char quote = 0; end < xml.size(); ++end) {
      if (quote) {
        if (xml[end] == quote) quote = 0;
      } else if (xml[end] == '"' || xml[end] == '\'') {
        quote = xml[end];
      } else if (xml[end] == '>') {
        break;
      }
    }
    if (end >= xml.size()) return;
    if (closing) --depth;
    else if (xml[end - 1] != '/' && ++depth > kMaxXmlDepth)
      throw Error(where + ": not a valid URDF: XML elements nested more than " + std::to_string(kMaxXmlDepth) + " levels deep");
    at = end;
  }
}

// urdfdom before 5.1 passes some attribute values to console_bridge as the printf format of its
// error messages (ros/urdfdom#243): a '%n' in a URDF writes through a garbage pointer. A '%'
// outside comments is refused before urdfdom sees the file; URDF names and numbers never need one.
void check_no_percent(const std::string& xml, const std::string& where) {
  std::size_t at = 0;
  while (at < xml.size()) {
    const std::size_t comment = xml.find("<!--", at);
    const std::size_t percent = xml.find('%', at);
    if (percent == std::string::npos) return;
    if (comment < percent) {
      const std::size_t end = xml.find("-->", comment + 4);
      if (end == std::string::npos) return;  // unterminated comment: urdfdom reports it
      at = end + 3;
      continue;
    }
    const auto line = 1 + std::count(xml.begin(), xml.begin() + static_cast<std::ptrdiff_t>(percent), '\n');
    throw Error(where + ": line " + std::to_string(line) +
                ": not a valid URDF for rdsim: '%' outside a comment (urdfdom would read it as a printf directive)");
  }
}

// TinyXML 2.6 (urdfdom's XML parser on Debian 12) steps over a UTF-8 character by the length its
// lead byte announces, up to 4 bytes, without looking for the end of the text: a file ending in
// the middle of a character made it read past the end of the buffer (found by fuzz_urdf). The
// text goes to it followed by this many NUL bytes, so such a step lands on a NUL and parsing stops.
constexpr std::size_t kTinyXmlPadding = 8;

urdf::ModelInterfaceSharedPtr parse_with_messages(const std::string& xml, const std::string& where) {
  check_xml_depth(xml, where);
  check_no_percent(xml, where);
  std::lock_guard<std::mutex> lock(parser_mutex());
  MessageCollector collector;
  console_bridge::useOutputHandler(&collector);
  urdf::ModelInterfaceSharedPtr model;
  std::string thrown;
  try {
    model = urdf::parseURDF(xml + std::string(kTinyXmlPadding, '\0'));
  } catch (const std::exception& e) {
    thrown = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  // urdfdom reports some bad values (a mass "nan") as errors yet returns a model with the value
  // replaced by 0: any error it reports makes the file invalid.
  if (!model || !collector.messages.empty()) {
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

// A number as the message shows it ("nan", "inf", "1e+30").
std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

bool finite(const urdf::Pose& p) {
  return std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z) &&
         std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) && std::isfinite(p.rotation.z) &&
         std::isfinite(p.rotation.w);
}

// Physical limits on what a link may carry: beyond them Bullet's integration breaks down, long
// before anything a robot could be. (No robot link weighs more than 100 t nor has a radius of
// gyration above 100 m.)
constexpr double kMaxMass = 1e5;                   // kg
constexpr double kMaxGyrationRadius = 100.0;       // m
constexpr double kTriangleSlack = 1e-6;            // relative, for rounding in the URDF's numbers

// Mass and inertia of a link (its mass may be 0 only when nothing moves it: `moving` is whether
// its own joint is movable). The inertia about the centre of mass must be a physical one:
// positive definite, principal moments obeying the triangle inequality (I1 + I2 >= I3), and not
// absurdly large for the mass.
void check_inertial(const Link& link, bool moving, const std::string& where) {
  const std::string ctx = "link \"" + link.name + "\": ";
  const double m = link.inertial.mass;
  if (moving && !(m > 0.0))
    fail(where, ctx + "mass " + num(m) + ": a link on a movable joint needs a mass > 0 (Bullet cannot accelerate a massless body)");
  if (!(m <= kMaxMass)) fail(where, ctx + "mass " + num(m) + " kg is out of range (at most " + num(kMaxMass) + " kg)");
  const Eigen::Matrix3d& I = link.inertial.inertia;
  if (m == 0.0) return;  // a massless decoration welded to its parent: its inertia does nothing
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d p = eig.eigenvalues();  // ascending
  if (!(p[0] > 0.0))
    fail(where, ctx + "inertia (ixx " + num(I(0, 0)) + ", iyy " + num(I(1, 1)) + ", izz " + num(I(2, 2)) +
                    ") is not positive definite (smallest principal moment " + num(p[0]) + ")");
  if (p[0] + p[1] < p[2] * (1.0 - kTriangleSlack))
    fail(where, ctx + "inertia principal moments " + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) +
                    " break the triangle inequality (I1 + I2 >= I3): no body has such an inertia");
  if (!(std::sqrt(p[2] / m) <= kMaxGyrationRadius))
    fail(where, ctx + "inertia " + num(p[2]) + " kg m^2 is implausible for a mass of " + num(m) + " kg (radius of gyration " +
                    num(std::sqrt(p[2] / m)) + " m, at most " + num(kMaxGyrationRadius) + " m)");
}

// What to_shape needs to read a <mesh>: the URDF's name (its folder is where relative paths start),
// the search path, and whether the element is a <collision> (which gets a convex hull).
struct MeshContext {
  const std::string& where;
  const UrdfLoadOptions& options;
  bool collision = false;
};

MeshGeometry to_mesh(const urdf::Mesh& m, const MeshContext& mc, const std::string& ctx) {
  MeshGeometry g;
  g.uri = m.filename;
  g.scale = Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z);
  const std::string prefix = ctx + "mesh \"" + one_line(g.uri, 200) + "\": ";
  try {
    if (!g.scale.allFinite() || !(g.scale.cwiseAbs().minCoeff() > 0.0))
      throw Error("scale (" + num(g.scale.x()) + " " + num(g.scale.y()) + " " + num(g.scale.z()) +
                  ") must be finite and non-zero in x, y and z");
    g.file = resolve_mesh_path(g.uri, mc.where, mc.options.search_path);
    g.mesh = load_mesh(g.file, g.scale);
    if (mc.collision) g.hull = load_convex_hull(g.file, g.scale);
  } catch (const Error& e) {
    fail(mc.where, prefix + e.what());
  }
  return g;
}

Shape to_shape(const urdf::GeometrySharedPtr& g, const urdf::Pose& origin, const MeshContext& mc,
               const std::string& link) {
  const std::string& where = mc.where;
  const std::string ctx = "link \"" + link + "\": ";
  if (!g) fail(where, ctx + "a collision/visual element has no <geometry>");
  if (!finite(origin)) fail(where, ctx + "a collision/visual <origin> is not finite");
  Shape s;
  s.origin = to_isometry(origin);
  switch (g->type) {
    case urdf::Geometry::BOX: {
      const auto& d = std::static_pointer_cast<urdf::Box>(g)->dim;
      s.type = ShapeType::Box;
      s.size = Eigen::Vector3d(d.x, d.y, d.z);
      if (!(s.size.minCoeff() > 0.0) || !s.size.allFinite())
        fail(where, ctx + "box size (" + num(d.x) + " " + num(d.y) + " " + num(d.z) + ") must be finite and positive in x, y and z");
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto c = std::static_pointer_cast<urdf::Cylinder>(g);
      s.type = ShapeType::Cylinder;
      s.radius = c->radius;
      s.length = c->length;
      if (!(s.radius > 0.0 && s.length > 0.0) || !std::isfinite(s.radius) || !std::isfinite(s.length))
        fail(where, ctx + "cylinder radius " + num(s.radius) + " and length " + num(s.length) + " must be finite and positive");
      break;
    }
    case urdf::Geometry::SPHERE:
      s.type = ShapeType::Sphere;
      s.radius = std::static_pointer_cast<urdf::Sphere>(g)->radius;
      if (!(s.radius > 0.0) || !std::isfinite(s.radius)) fail(where, ctx + "sphere radius " + num(s.radius) + " must be finite and positive");
      break;
    case urdf::Geometry::MESH:
      s.type = ShapeType::Mesh;
      s.mesh = to_mesh(*std::static_pointer_cast<urdf::Mesh>(g), mc, ctx);
      break;
    default:
      fail(where, ctx + "unknown geometry type");
  }
  return s;
}

Link to_link(const urdf::Link& in, const std::string& where, const UrdfLoadOptions& options) {
  Link out;
  out.name = in.name;
  if (in.inertial) {
    const urdf::Inertial& i = *in.inertial;
    if (!(i.mass >= 0.0) || !std::isfinite(i.mass))
      fail(where, "link \"" + in.name + "\": mass " + num(i.mass) + " must be finite and >= 0");
    if (!finite(i.origin)) fail(where, "link \"" + in.name + "\": <inertial><origin> is not finite");
    out.inertial.mass = i.mass;
    out.inertial.origin = to_isometry(i.origin);
    out.inertial.inertia << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
    if (!(i.ixx >= 0.0 && i.iyy >= 0.0 && i.izz >= 0.0) || !out.inertial.inertia.allFinite())
      fail(where, "link \"" + in.name + "\": inertia (ixx " + num(i.ixx) + ", iyy " + num(i.iyy) + ", izz " + num(i.izz) + ", ixy " +
                      num(i.ixy) + ", ixz " + num(i.ixz) + ", iyz " + num(i.iyz) + ") must be finite with ixx, iyy, izz >= 0");
  }
  for (const auto& c : in.collision_array)
    out.collisions.push_back(to_shape(c->geometry, c->origin, MeshContext{where, options, true}, in.name));
  for (const auto& v : in.visual_array) {
    VisualShape vs;
    vs.shape = to_shape(v->geometry, v->origin, MeshContext{where, options, false}, in.name);
    // A mesh with colours of its own and no URDF material shows its own colours (drawn times rgba).
    if (vs.shape.type == ShapeType::Mesh && !v->material && !vs.shape.mesh.mesh->colors.empty())
      vs.rgba = Eigen::Vector4f::Ones();
    if (v->material) {
      const urdf::Color& c = v->material->color;
      vs.rgba = Eigen::Vector4f(c.r, c.g, c.b, c.a);
      if (!(vs.rgba.minCoeff() >= 0.0f && vs.rgba.maxCoeff() <= 1.0f))
        fail(where, "link \"" + in.name + "\": material rgba must be four numbers in [0, 1]");
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
  if (!finite(in.parent_to_joint_origin_transform)) fail(where, ctx + "<origin> is not finite");
  j.origin = to_isometry(in.parent_to_joint_origin_transform);
  if (j.movable()) {
    const Eigen::Vector3d axis(in.axis.x, in.axis.y, in.axis.z);
    if (!(axis.norm() > 1e-9) || !axis.allFinite()) fail(where, ctx + "<axis> must be finite and not zero");
    j.axis = axis.normalized();
    if (!in.limits) fail(where, ctx + "a movable joint needs <limit effort=... velocity=...>");
    j.effort = in.limits->effort;
    j.velocity = in.limits->velocity;
    if (!(j.effort > 0.0) || !std::isfinite(j.effort)) fail(where, ctx + "<limit effort> " + num(j.effort) + " must be finite and > 0");
    if (!(j.velocity > 0.0) || !std::isfinite(j.velocity))
      fail(where, ctx + "<limit velocity> " + num(j.velocity) + " must be finite and > 0");
  }
  if (j.type == JointType::Continuous) {
    j.lower = -std::numeric_limits<double>::infinity();
    j.upper = std::numeric_limits<double>::infinity();
  } else if (j.type != JointType::Fixed) {
    j.lower = in.limits->lower;
    j.upper = in.limits->upper;
    if (!std::isfinite(j.lower) || !std::isfinite(j.upper) || !(j.lower <= j.upper))
      fail(where, ctx + "<limit lower> " + num(j.lower) + " and upper " + num(j.upper) + " must be finite with lower <= upper");
  }
  if (in.dynamics) {
    j.damping = in.dynamics->damping;
    j.friction = in.dynamics->friction;
    if (!(j.damping >= 0.0) || !(j.friction >= 0.0) || !std::isfinite(j.damping) || !std::isfinite(j.friction))
      fail(where, ctx + "<dynamics damping> " + num(j.damping) + " and friction " + num(j.friction) + " must be finite and >= 0");
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

RobotModel parse_urdf(const std::string& xml, const std::string& where, const UrdfLoadOptions& options) {
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
    model.links.push_back(to_link(*link, where, options));
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
  for (size_t li = 0; li < model.links.size(); ++li)
    check_inertial(model.links[li], li > 0 && model.joints[li - 1].movable(), where);
  return model;
}

RobotModel load_urdf(const std::string& path, const UrdfLoadOptions& options) {
  return parse_urdf(read_file(path, max_urdf_bytes), path, options);
}

}  // namespace rdsim
