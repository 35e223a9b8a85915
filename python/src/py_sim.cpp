// rdsim._rdsim.sim: the simulation level (sim/physics_world.hpp, robot.hpp, ik.hpp) for tools that
// compare rdsim with another simulator step by step (tools/fidelity) or script a robot directly.
// The package's rdsim.sim re-exports it. World owns everything; a Robot handle keeps its World alive.
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/sim/ik.hpp"
#include "rdsim/sim/kinematics.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace rdsim::python {
namespace {

// Finite float64 values from any 1-d sequence of `n` numbers; rdsim::Error naming `what` otherwise.
Eigen::VectorXd read_values(const py::handle& h, py::ssize_t n, const std::string& what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a) {
    PyErr_Clear();
    throw Error(what + ": expected a sequence of " + std::to_string(n) + " numbers, got a Python " + type_name(h));
  }
  if (a.ndim() != 1 || a.shape(0) != n)
    throw Error(what + ": expected " + std::to_string(n) + " numbers, got an array of shape " +
                py::str(py::tuple(py::cast(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim())))).cast<std::string>());
  Eigen::VectorXd v(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    v[i] = a.at(i);
    if (!std::isfinite(v[i])) throw Error(what + ": value " + std::to_string(i) + " is not finite");
  }
  return v;
}

Eigen::Isometry3f read_pose(const py::handle& position, const py::handle& orientation, const std::string& what) {
  const Eigen::VectorXd p = read_values(position, 3, what + ": position");
  const Eigen::VectorXd q = read_values(orientation, 4, what + ": orientation (x, y, z, w)");
  if (q.norm() < 1e-9) throw Error(what + ": orientation: expected a non-zero quaternion (x, y, z, w)");
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.linear() = Eigen::Quaternionf(static_cast<float>(q[3]), static_cast<float>(q[0]), static_cast<float>(q[1]),
                                     static_cast<float>(q[2])).normalized().toRotationMatrix();
  pose.translation() = p.cast<float>();
  return pose;
}

py::array_t<double> to_array(const Eigen::VectorXf& v) {
  py::array_t<double> a(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) a.mutable_at(i) = static_cast<double>(v[i]);
  return a;
}

JointDrive read_drive(const std::string& drive) {
  if (drive == "position_motor") return JointDrive::ConstraintMotor;
  if (drive == "computed_torque") return JointDrive::ComputedTorque;
  throw Error("rdsim.sim.World.add_robot: drive: expected \"position_motor\" or \"computed_torque\", got \"" + drive + "\"");
}

// The robot dof (movable joints in model order) of joint `name`; rdsim::Error naming `key` otherwise.
int dof_named(const RobotModel& model, const std::string& name, const char* key) {
  const int joint = model.joint_index(name);
  if (joint < 0 || !model.joints[static_cast<size_t>(joint)].movable())
    throw Error(std::string("rdsim.sim.World.add_robot: ") + key + ": \"" + name + "\" is not a movable joint of " +
                model.source);
  int dof = 0;
  for (int j = 0; j < joint; ++j) dof += model.joints[static_cast<size_t>(j)].movable() ? 1 : 0;
  return dof;
}

struct WorldData {
  std::unique_ptr<PhysicsWorld> world;
};

class PyRobot {
public:
  PyRobot(std::shared_ptr<WorldData> data, int body) : data_(std::move(data)), body_(body) {}

  Robot& robot() const { return data_->world->robot(body_); }
  int body() const { return body_; }
  int dof() const { return robot().dof(); }

  std::vector<std::string> joint_names() const {
    std::vector<std::string> out;
    for (int i = 0; i < dof(); ++i) out.push_back(robot().model().joints[static_cast<size_t>(robot().dof_joint(i))].name);
    return out;
  }
  std::vector<std::string> link_names() const {
    std::vector<std::string> out;
    for (const Link& l : robot().model().links) out.push_back(l.name);
    return out;
  }
  // Per dof: lower, upper, effort, velocity limits (URDF).
  py::array_t<double> joint_limit(int which) const {
    Eigen::VectorXf v(dof());
    for (int i = 0; i < dof(); ++i) {
      const Joint& j = robot().model().joints[static_cast<size_t>(robot().dof_joint(i))];
      const double values[4] = {j.lower, j.upper, j.effort, j.velocity};
      v[i] = static_cast<float>(values[which]);
    }
    return to_array(v);
  }

  void set_position_targets(const py::handle& q) {
    robot().set_position_targets(read_values(q, dof(), "Robot.set_position_targets").cast<float>());
  }
  void set_gains(double kp, double kd) {
    if (!std::isfinite(kp) || !std::isfinite(kd) || kp < 0.0 || kd < 0.0)
      throw Error("Robot.set_gains: expected finite gains >= 0");
    robot().set_gains(static_cast<float>(kp), static_cast<float>(kd));
  }
  void reset_joints(const py::handle& q) {
    robot().reset_joints(read_values(q, dof(), "Robot.reset_joints").cast<float>());
  }
  py::array_t<double> joint_positions() const { return to_array(robot().joint_positions()); }
  // Robot::state() as (positions, velocities, targets), for set_state.
  py::tuple state() const {
    const RobotState s = robot().state();
    return py::make_tuple(s.positions, s.velocities, s.targets);
  }
  void set_state(const py::tuple& t) {
    if (t.size() != 3) throw Error("Robot.set_state: expected the (positions, velocities, targets) that state() returned");
    RobotState s;
    const Eigen::VectorXd p = read_values(t[0], dof(), "Robot.set_state: positions");
    const Eigen::VectorXd v = read_values(t[1], dof(), "Robot.set_state: velocities");
    const Eigen::VectorXd g = read_values(t[2], dof(), "Robot.set_state: targets");
    for (int i = 0; i < dof(); ++i) {
      s.positions.push_back(static_cast<float>(p[i]));
      s.velocities.push_back(static_cast<float>(v[i]));
      s.targets.push_back(static_cast<float>(g[i]));
    }
    robot().set_state(s, "Robot.set_state");
  }
  py::array_t<double> joint_velocities() const { return to_array(robot().joint_velocities()); }
  py::array_t<double> position_targets() const { return to_array(robot().position_targets()); }

  int link_index(const py::handle& link) const {
    const RobotModel& m = robot().model();
    if (py::isinstance<py::str>(link)) return m.require_link(link.cast<std::string>());
    if (py::isinstance<py::int_>(link) && !py::isinstance<py::bool_>(link)) {
      const int i = link.cast<int>();
      if (i < 0 || i >= static_cast<int>(m.links.size()))
        throw Error(m.source + ": link index " + std::to_string(i) + " is out of range (the robot has " +
                    std::to_string(m.links.size()) + " links)");
      return i;
    }
    throw Error("Robot: link: expected a link name (str) or index (int), got a Python " + type_name(link));
  }
  // A link's URDF frame in the world: (position (3,), orientation quaternion (x, y, z, w)).
  py::tuple link_pose(const py::handle& link) const {
    const Eigen::Isometry3f pose = robot().link_pose(link_index(link));
    const Eigen::Quaternionf q(pose.linear());
    return py::make_tuple(to_array(pose.translation()), to_array(Eigen::Vector4f(q.x(), q.y(), q.z(), q.w())));
  }
  // (mass kg, principal moments kg m^2 (3,)) as Bullet simulates the link.
  py::tuple link_inertia(const py::handle& link) const {
    const Robot::LinkInertia i = robot().link_inertia(link_index(link));
    py::array_t<double> moments(3);
    for (int k = 0; k < 3; ++k) moments.mutable_at(k) = i.moments[k];
    return py::make_tuple(i.mass, moments);
  }
  py::array_t<double> link_position(const py::handle& link) const {
    return to_array(robot().link_pose(link_index(link)).translation());
  }
  // Every link's origin, (links, 3).
  py::array_t<double> link_positions() const {
    const int n = static_cast<int>(robot().model().links.size());
    py::array_t<double> a({n, 3});
    for (int l = 0; l < n; ++l) {
      const Eigen::Vector3f p = robot().link_pose(l).translation();
      for (int k = 0; k < 3; ++k) a.mutable_at(l, k) = static_cast<double>(p[k]);
    }
    return a;
  }

  // sim::null_space_ik on the chain from the root link to `link`: joint angles (every dof; the joints
  // off the chain keep `start`) for the link's origin at `target` (world frame).
  py::array_t<double> null_space_ik(const py::handle& link, const py::handle& target, const py::object& start,
                                    const py::object& rest, int iterations, double residual_threshold) {
    const int tip = link_index(link);
    const KinematicChain& chain = chain_to(tip);
    const std::string where = "Robot.null_space_ik";
    if (iterations < 1) throw Error(where + ": iterations: expected >= 1");
    if (!(residual_threshold >= 0.0)) throw Error(where + ": residual_threshold: expected >= 0");
    const Eigen::VectorXd goal = read_values(target, 3, where + ": target");
    const Eigen::VectorXd q0 = start.is_none() ? robot().joint_positions().cast<double>().eval()
                                               : read_values(start, dof(), where + ": start");
    const Eigen::VectorXd r = rest.is_none() ? Eigen::VectorXd::Zero(dof()) : read_values(rest, dof(), where + ": rest");
    JointVector qc(chain.dof()), rc(chain.dof());
    for (int i = 0; i < chain.dof(); ++i) {
      const int d = robot().dof_of_joint(chain.model_joint(i));
      qc[i] = q0[d];
      rc[i] = r[d];
    }
    const Eigen::Isometry3d base = robot().link_pose(0).cast<double>();
    NullSpaceIkOptions options;
    options.iterations = iterations;
    options.tolerance = residual_threshold;
    const JointVector solution = rdsim::null_space_ik(chain, base.inverse() * Eigen::Vector3d(goal), qc, rc, options);
    Eigen::VectorXd out_d = q0;
    for (int i = 0; i < chain.dof(); ++i) out_d[robot().dof_of_joint(chain.model_joint(i))] = solution[i];
    py::array_t<double> a(dof());
    for (int i = 0; i < dof(); ++i) a.mutable_at(i) = out_d[i];
    return a;
  }

  // The friction coefficient of link `link` (Robot::set_link_friction), by name.
  void set_link_friction(const std::string& link, double friction) {
    robot().set_link_friction(robot().model().require_link(link), static_cast<float>(friction));
  }

private:
  const KinematicChain& chain_to(int tip) {
    auto it = chains_.find(tip);
    if (it == chains_.end())
      it = chains_.emplace(tip, std::make_shared<KinematicChain>(robot().model(), robot().model().links[static_cast<size_t>(tip)].name)).first;
    return *it->second;
  }

  std::shared_ptr<WorldData> data_;
  int body_;
  std::map<int, std::shared_ptr<KinematicChain>> chains_;  // shared: a PyRobot is copied into Python
};

class PyWorld {
  // A Python int or float (not a bool) as a double; rdsim.Error naming `key` otherwise.
  static double read_number(const py::object& value, const char* key) {
    const bool number = py::isinstance<py::float_>(value) || (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value));
    if (!number)
      throw Error(std::string("rdsim.sim.World: ") + key + ": expected None or a number, got " + py::repr(value).cast<std::string>());
    return value.cast<double>();
  }

public:
  // residual_threshold: None = the default (0, or pybullet's 1e-7 with pybullet_solver); a number wins.
  PyWorld(double time_step, int solver_iterations, const py::handle& gravity, const py::object& residual_threshold,
          bool pybullet_solver_settings, const py::object& contact_warm_start, double joint_row_warm_start,
          bool joint_block_solve, bool mass_matrix_responses, bool skip_separated_pairs)
      : data_(std::make_shared<WorldData>()) {
    WorldSettings s;
    s.time_step = time_step;
    s.solver_iterations = solver_iterations;
    s.gravity = read_values(gravity, 3, "rdsim.sim.World: gravity").cast<float>();
    if (pybullet_solver_settings) s = pybullet_solver(s);
    if (!residual_threshold.is_none()) {
      const double threshold = read_number(residual_threshold, "solver_residual_threshold");
      if (!(threshold >= 0.0))
        throw Error("rdsim.sim.World: solver_residual_threshold: expected None or a number >= 0, got " +
                    py::repr(residual_threshold).cast<std::string>());
      s.solver_residual_threshold = threshold;
    }
    // contact_warm_start: None = the default (Bullet's 0.85, or pybullet's 0.1 with pybullet_solver).
    if (!contact_warm_start.is_none()) s.warmstarting_factor = read_number(contact_warm_start, "contact_warm_start");
    s.joint_row_warm_start = joint_row_warm_start;  // PhysicsWorld checks the ranges
    s.joint_block_solve = joint_block_solve;
    s.mass_matrix_responses = mass_matrix_responses;
    s.skip_separated_pairs = skip_separated_pairs;
    data_->world = std::make_unique<PhysicsWorld>(s);
  }

  PyRobot add_robot(const std::string& urdf, const py::handle& position, const py::handle& orientation,
                    const std::string& drive, double kp, double kd, bool limit_constraints, bool speed_limits,
                    double link_damping, bool inertia_from_shapes, bool joint_damping,
                    const std::vector<std::string>& motor_joints,
                    const std::vector<std::vector<std::string>>& coupled_joints) {
    RobotOptions o;
    o.drive = read_drive(drive);
    if (!std::isfinite(kp) || !std::isfinite(kd) || kp < 0.0 || kd < 0.0)
      throw Error("rdsim.sim.World.add_robot: expected finite gains >= 0");
    o.position_gain = static_cast<float>(kp);
    o.velocity_gain = static_cast<float>(kd);
    o.limit_constraints = limit_constraints;
    o.motor_speed_limits = speed_limits;
    if (!(link_damping >= 0.0 && link_damping <= 1.0))
      throw Error("rdsim.sim.World.add_robot: link_damping: expected a number in [0, 1]");
    o.link_damping = static_cast<float>(link_damping);
    o.inertia_from_shapes = inertia_from_shapes;
    o.joint_damping = joint_damping;
    const Eigen::Isometry3f pose = read_pose(position, orientation, "rdsim.sim.World.add_robot");
    const RobotModel model = load_urdf(urdf);
    for (const std::string& name : motor_joints) o.motor_dofs.push_back(dof_named(model, name, "motor_joints"));
    for (const std::vector<std::string>& pair : coupled_joints) {
      if (pair.size() != 2) throw Error("rdsim.sim.World.add_robot: coupled_joints: expected pairs of joint names");
      o.coupled_dofs.emplace_back(dof_named(model, pair[0], "coupled_joints"), dof_named(model, pair[1], "coupled_joints"));
    }
    return PyRobot(data_, data_->world->add_robot(model, pose, o).body());
  }

  // A free body's friction coefficient (PhysicsWorld::set_free_body_friction).
  void set_friction(int body, double friction) {
    data_->world->set_free_body_friction(body, static_cast<float>(friction));
  }

  int add_static_body(const std::string& urdf, const py::handle& position, const py::handle& orientation) {
    const Eigen::Isometry3f pose = read_pose(position, orientation, "rdsim.sim.World.add_static_body");
    return data_->world->add_static_body(load_urdf(urdf), pose);
  }

  int add_free_body(const std::string& urdf, const py::handle& position, const py::handle& orientation) {
    const Eigen::Isometry3f pose = read_pose(position, orientation, "rdsim.sim.World.add_free_body");
    return data_->world->add_free_body(load_urdf(urdf), pose);
  }
  void set_body_pose(int body, const py::handle& position, const py::handle& orientation) {
    data_->world->set_static_pose(body, read_pose(position, orientation, "rdsim.sim.World.set_body_pose"));
  }
  // Where a static or free body is now: (position (3,), orientation (x, y, z, w)).
  py::tuple body_pose(int body) const {
    const Eigen::Isometry3f pose = data_->world->static_pose(body);
    const Eigen::Quaternionf q(pose.linear());
    return py::make_tuple(to_array(pose.translation()), to_array(Eigen::Vector4f(q.x(), q.y(), q.z(), q.w())));
  }

  void step(int steps) {
    if (steps < 0) throw Error("rdsim.sim.World.step: steps: expected >= 0");
    py::gil_scoped_release unlocked;
    for (int i = 0; i < steps; ++i) data_->world->step();
  }
  double time() const { return data_->world->time(); }
  double time_step() const { return data_->world->settings().time_step; }
  int solver_iterations() const { return data_->world->settings().solver_iterations; }
  // What the steps so far cost (PhysicsWorld::work).
  py::dict work() const {
    const PhysicsWorld::Work w = data_->world->work();
    py::dict d;
    d["steps"] = w.steps;
    d["solver_iterations"] = w.solver_iterations;
    d["pairs_skipped"] = w.pairs_skipped;
    return d;
  }

private:
  std::shared_ptr<WorldData> data_;
};

}  // namespace

void bind_sim(py::module_& parent) {
  py::module_ m = parent.def_submodule("sim", "rdsim's simulation level: a Bullet world, robots from URDFs, IK");
  py::class_<PyRobot>(m, "Robot", "A fixed-base robot in a World (made by World.add_robot).")
      .def_property_readonly("body", &PyRobot::body)
      .def_property_readonly("dof", &PyRobot::dof)
      .def_property_readonly("joint_names", &PyRobot::joint_names, "The movable joints, in dof order.")
      .def_property_readonly("link_names", &PyRobot::link_names, "Every link, in tree order (0 = root).")
      .def_property_readonly("lower", [](const PyRobot& r) { return r.joint_limit(0); })
      .def_property_readonly("upper", [](const PyRobot& r) { return r.joint_limit(1); })
      .def_property_readonly("effort", [](const PyRobot& r) { return r.joint_limit(2); })
      .def_property_readonly("max_velocity", [](const PyRobot& r) { return r.joint_limit(3); })
      .def("set_position_targets", &PyRobot::set_position_targets, py::arg("q"))
      .def("set_gains", &PyRobot::set_gains, py::arg("position_gain"), py::arg("velocity_gain"))
      .def("reset_joints", &PyRobot::reset_joints, py::arg("q"))
      .def("joint_positions", &PyRobot::joint_positions)
      .def("joint_velocities", &PyRobot::joint_velocities)
      .def("state", &PyRobot::state)
      .def("set_state", &PyRobot::set_state, py::arg("state"))
      .def("position_targets", &PyRobot::position_targets)
      .def("set_link_friction", &PyRobot::set_link_friction, py::arg("link"), py::arg("friction"),
           "A link's friction coefficient (with friction anchors).")
      .def("link_index", &PyRobot::link_index, py::arg("link"))
      .def("link_pose", &PyRobot::link_pose, py::arg("link"))
      .def("link_position", &PyRobot::link_position, py::arg("link"))
      .def("link_inertia", &PyRobot::link_inertia, py::arg("link"))
      .def("link_positions", &PyRobot::link_positions)
      .def("null_space_ik", &PyRobot::null_space_ik, py::arg("link"), py::arg("target"), py::arg("start") = py::none(),
           py::arg("rest") = py::none(), py::arg("iterations") = 20, py::arg("residual_threshold") = 1e-4);
  py::class_<PyWorld>(m, "World", "A Bullet multibody world (sim::PhysicsWorld).")
      .def(py::init<double, int, const py::handle&, const py::object&, bool, const py::object&, double, bool, bool,
                    bool>(),
           py::arg("time_step") = 1.0 / 240.0, py::arg("solver_iterations") = 50,
           py::arg("gravity") = py::make_tuple(0.0, 0.0, -9.8), py::arg("solver_residual_threshold") = py::none(),
           py::arg("pybullet_solver") = false, py::arg("contact_warm_start") = py::none(), py::arg("joint_row_warm_start") = 0.0,
           py::arg("joint_block_solve") = false, py::arg("mass_matrix_responses") = false,
           py::arg("skip_separated_pairs") = true)
      .def("add_robot", &PyWorld::add_robot, py::arg("urdf"), py::arg("position") = py::make_tuple(0.0, 0.0, 0.0),
           py::arg("orientation") = py::make_tuple(0.0, 0.0, 0.0, 1.0), py::arg("drive") = "position_motor",
           py::arg("position_gain") = 1.0, py::arg("velocity_gain") = 1.0, py::arg("limit_constraints") = true,
           py::arg("speed_limits") = true, py::arg("link_damping") = 0.0, py::arg("inertia_from_shapes") = false,
           py::arg("joint_damping") = false, py::arg("motor_joints") = std::vector<std::string>{},
           py::arg("coupled_joints") = std::vector<std::vector<std::string>>{})
      .def("set_friction", &PyWorld::set_friction, py::arg("body"), py::arg("friction"),
           "A free body's friction coefficient (with friction anchors).")
      .def("add_static_body", &PyWorld::add_static_body, py::arg("urdf"),
           py::arg("position") = py::make_tuple(0.0, 0.0, 0.0), py::arg("orientation") = py::make_tuple(0.0, 0.0, 0.0, 1.0))
      .def("add_free_body", &PyWorld::add_free_body, py::arg("urdf"),
           py::arg("position") = py::make_tuple(0.0, 0.0, 0.0), py::arg("orientation") = py::make_tuple(0.0, 0.0, 0.0, 1.0))
      .def("body_pose", &PyWorld::body_pose, py::arg("body"))
      .def("set_body_pose", &PyWorld::set_body_pose, py::arg("body"), py::arg("position"),
           py::arg("orientation") = py::make_tuple(0.0, 0.0, 0.0, 1.0))
      .def("step", &PyWorld::step, py::arg("steps") = 1)
      .def_property_readonly("time", &PyWorld::time)
      .def_property_readonly("time_step", &PyWorld::time_step)
      .def_property_readonly("solver_iterations", &PyWorld::solver_iterations)
      .def("work", &PyWorld::work, "Steps, solver iterations and skipped narrow-phase pairs so far.");
}

}  // namespace rdsim::python
