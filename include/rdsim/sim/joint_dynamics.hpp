#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "rdsim/sim/robot_model.hpp"

// Joint-space dynamics of a fixed-base robot tree (our own: recursive Newton-Euler for the
// forces, composite rigid bodies for the mass matrix):
//   tau = M(q) qdd + c(q, qd) + g(q)
// Robot uses it to drive its joints (see robot.hpp); tests use it against Bullet.
// Vectors hold one value per movable joint, in tree order. Scratch space is allocated once, so
// calls do not allocate (the methods are therefore not const and not thread-safe).
namespace rdsim {

class JointDynamics {
public:
  // `inertials`: one per link, in that link's frame (what the physics simulates; by default the URDF's).
  JointDynamics(const RobotModel& model, const std::vector<Inertial>& inertials);
  explicit JointDynamics(const RobotModel& model);

  int dof() const { return dof_; }

  // Joint forces for accelerations `qdd` at (q, qd) under `gravity` (root-link frame, m/s^2).
  void inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                        const Eigen::Vector3d& gravity, Eigen::VectorXd& tau);
  // M(q) (dof x dof) and the bias c(q, qd) + g(q), sharing one kinematics pass.
  void mass_matrix_and_bias(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::Vector3d& gravity,
                            Eigen::MatrixXd& mass, Eigen::VectorXd& bias);
  // M(q) alone.
  void mass_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& mass);

private:
  struct Body {
    int parent = -1;         // link index
    int dof = -1;            // -1 for a fixed joint
    bool prismatic = false;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // joint frame in the parent link frame
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    double mass = 0.0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();          // in the link frame
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();      // about the com, link axes
  };
  // Per-link scratch (frame quantities of the link, in its own axes).
  struct State {
    Eigen::Matrix3d rotation;      // link axes in the parent's axes
    Eigen::Vector3d offset;        // link origin in the parent frame
    Eigen::Vector3d w, dw, a;      // angular velocity, angular and linear (origin) acceleration
    Eigen::Vector3d f, n;          // force and moment (about the origin) the parent applies
  };

  // A link's subtree as one rigid body, about the link's origin in its axes.
  struct Composite {
    double mass = 0.0;
    Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();  // mass times centre of mass
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  };

  void kinematics(const Eigen::VectorXd& q);
  void composite_inertia();
  // M from the kinematics and composite inertias of the last kinematics() / composite_inertia().
  void assemble_mass(Eigen::MatrixXd& mass) const;
  // One Newton-Euler pass over links [1, n) with the kinematics from kinematics().
  void newton_euler(const Eigen::VectorXd* qd, const Eigen::VectorXd& qdd, const Eigen::Vector3d& gravity,
                    Eigen::VectorXd& tau);

  int dof_ = 0;
  std::vector<Body> bodies_;
  std::vector<State> state_;
  std::vector<Composite> own_, composite_;  // own_: each link alone
  Eigen::VectorXd unit_;  // scratch: zero accelerations
};

}  // namespace rdsim
