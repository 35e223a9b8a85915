#include "rdsim/sim/joint_dynamics.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

std::vector<Inertial> urdf_inertials(const RobotModel& model) {
  std::vector<Inertial> out;
  for (const auto& l : model.links) out.push_back(l.inertial);
  return out;
}

}  // namespace

JointDynamics::JointDynamics(const RobotModel& model) : JointDynamics(model, urdf_inertials(model)) {}

JointDynamics::JointDynamics(const RobotModel& model, const std::vector<Inertial>& inertials) {
  if (inertials.size() != model.links.size())
    throw Error(model.source + ": expected one inertial per link");
  bodies_.resize(model.links.size());
  state_.resize(model.links.size());
  for (size_t i = 0; i < model.links.size(); ++i) {
    Body& b = bodies_[i];
    const Inertial& in = inertials[i];
    b.mass = in.mass;
    b.com = in.origin.translation();
    b.inertia = in.origin.linear() * in.inertia * in.origin.linear().transpose();
    if (i == 0) continue;
    const Joint& j = model.joints[i - 1];
    b.parent = j.parent_link;
    b.origin = j.origin;
    b.axis = j.axis;
    b.prismatic = j.type == JointType::Prismatic;
    if (j.movable()) b.dof = dof_++;
  }
  // Each link alone as a composite (about its origin), where composite_inertia() starts from.
  own_.resize(model.links.size());
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    Composite& c = own_[i];
    c.mass = b.mass;
    c.first_moment = b.mass * b.com;
    c.inertia = b.inertia + b.mass * (b.com.squaredNorm() * Eigen::Matrix3d::Identity() - b.com * b.com.transpose());
  }
  composite_ = own_;
  unit_ = Eigen::VectorXd::Zero(dof_);
}

void JointDynamics::kinematics(const Eigen::VectorXd& q) {
  for (size_t i = 1; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    State& s = state_[i];
    s.rotation = b.origin.linear();
    s.offset = b.origin.translation();
    if (b.dof < 0) continue;
    if (b.prismatic)
      s.offset += s.rotation * (b.axis * q[b.dof]);
    else
      s.rotation = s.rotation * Eigen::AngleAxisd(q[b.dof], b.axis).toRotationMatrix();
  }
}

void JointDynamics::newton_euler(const Eigen::VectorXd* qd, const Eigen::VectorXd& qdd,
                                 const Eigen::Vector3d& gravity, Eigen::VectorXd& tau) {
  // Gravity enters as an upward acceleration of the fixed root.
  State& root = state_[0];
  root.w.setZero();
  root.dw.setZero();
  root.a = -gravity;
  for (size_t i = 1; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    State& s = state_[i];
    const State& p = state_[static_cast<size_t>(b.parent)];
    const Eigen::Matrix3d rt = s.rotation.transpose();
    s.w = rt * p.w;
    s.dw = rt * p.dw;
    s.a = rt * (p.a + p.dw.cross(s.offset) + p.w.cross(p.w.cross(s.offset)));
    if (b.dof >= 0) {
      const double v = qd ? (*qd)[b.dof] : 0.0;
      const double acc = qdd[b.dof];
      if (b.prismatic) {
        s.a += 2.0 * s.w.cross(b.axis * v) + b.axis * acc;
      } else {
        s.dw += s.w.cross(b.axis * v) + b.axis * acc;
        s.w += b.axis * v;
      }
    }
    const Eigen::Vector3d a_com = s.a + s.dw.cross(b.com) + s.w.cross(s.w.cross(b.com));
    s.f = b.mass * a_com;
    s.n = b.inertia * s.dw + s.w.cross(b.inertia * s.w) + b.com.cross(s.f);
  }
  for (size_t i = bodies_.size() - 1; i >= 1; --i) {
    const Body& b = bodies_[i];
    const State& s = state_[i];
    if (b.dof >= 0) tau[b.dof] = b.prismatic ? b.axis.dot(s.f) : b.axis.dot(s.n);
    if (b.parent >= 1) {
      State& p = state_[static_cast<size_t>(b.parent)];
      const Eigen::Vector3d f = s.rotation * s.f;
      p.f += f;
      p.n += s.rotation * s.n + s.offset.cross(f);
    }
  }
}

void JointDynamics::inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                     const Eigen::Vector3d& gravity, Eigen::VectorXd& tau) {
  tau.resize(dof_);
  kinematics(q);
  newton_euler(&qd, qdd, gravity, tau);
}

void JointDynamics::mass_matrix_and_bias(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                         const Eigen::Vector3d& gravity, Eigen::MatrixXd& mass,
                                         Eigen::VectorXd& bias) {
  bias.resize(dof_);
  kinematics(q);
  unit_.setZero();
  newton_euler(&qd, unit_, gravity, bias);
  composite_inertia();
  assemble_mass(mass);
}

void JointDynamics::mass_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& mass) {
  kinematics(q);
  composite_inertia();
  assemble_mass(mass);
}

void JointDynamics::assemble_mass(Eigen::MatrixXd& mass) const {
  mass.setZero(dof_, dof_);  // joints on different branches do not couple
  // Composite-rigid-body algorithm: the force that a unit acceleration of joint j (from rest)
  // needs is the composite inertia of j's subtree times the joint's motion; carried up the
  // tree it gives column j of M at every ancestor joint.
  for (size_t i = 1; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (b.dof < 0) continue;
    const Composite& c = composite_[i];
    Eigen::Vector3d f, n;  // about link i's origin, link i's axes
    if (b.prismatic) {
      f = c.mass * b.axis;
      n = c.first_moment.cross(b.axis);
    } else {
      f = b.axis.cross(c.first_moment);
      n = c.inertia * b.axis;
    }
    mass(b.dof, b.dof) = b.prismatic ? b.axis.dot(f) : b.axis.dot(n);
    for (size_t k = i; bodies_[k].parent >= 1;) {
      const State& s = state_[k];
      f = s.rotation * f;
      n = s.rotation * n + s.offset.cross(f);
      k = static_cast<size_t>(bodies_[k].parent);
      const Body& a = bodies_[k];
      if (a.dof < 0) continue;
      mass(a.dof, b.dof) = a.prismatic ? a.axis.dot(f) : a.axis.dot(n);
      mass(b.dof, a.dof) = mass(a.dof, b.dof);
    }
  }
}

void JointDynamics::composite_inertia() {
  composite_ = own_;
  for (size_t i = bodies_.size() - 1; i >= 1; --i) {
    const int parent = bodies_[i].parent;
    if (parent < 1) continue;  // the fixed root's composite is never needed
    const Composite& c = composite_[i];
    const State& s = state_[i];
    Composite& p = composite_[static_cast<size_t>(parent)];
    const Eigen::Vector3d h = s.rotation * c.first_moment;  // about the child origin, parent axes
    const Eigen::Vector3d& o = s.offset;
    // Parallel-axis theorem for a body known by its first moment about a point `o` away.
    p.inertia += s.rotation * c.inertia * s.rotation.transpose() +
                 c.mass * (o.squaredNorm() * Eigen::Matrix3d::Identity() - o * o.transpose()) +
                 2.0 * o.dot(h) * Eigen::Matrix3d::Identity() - o * h.transpose() - h * o.transpose();
    p.first_moment += h + c.mass * o;
    p.mass += c.mass;
  }
}

}  // namespace rdsim
