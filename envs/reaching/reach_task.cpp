#include "rdsim/envs/reaching/reach_task.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/sim/ik.hpp"
#include "rdsim/sim/urdf_loader.hpp"

namespace rdsim {
namespace {

constexpr double kIkDamping = 0.02;  // m: keeps the step bounded near singular poses
// Metres of position error one radian of orientation error counts as, when moves hold the end
// effector's orientation (ReachTaskSpec::effector_orientation): solve_ik's default.
constexpr double kOrientationWeight = 0.2;
constexpr float kPybulletLinkDamping = 0.04f;  // 1/s: Bullet's btMultiBody default, which pybullet keeps
// The position-motor presets stop iterating once no row changes a velocity by more than about
// 0.03 mm/s (or mrad/s): a hundredth of pybullet's 1e-7 (its physics server's setting), which let
// the InMoov drift from the original's path by 8.6 mm on average over a 1,000-step random sequence
// (0.9 mm with 1e-9), for no speed the tighter threshold does not also give.
constexpr double kResidualThreshold = 1e-9;
// The position-motor presets' contact rows start each solve from the whole impulse they ended the
// last one with, where pybullet starts them from a tenth (warm starting 0.1). The paper button
// resting on the table needs about the same impulses step after step; rebuilding nine tenths of
// them was most of the iterations left after the joint rows' block solve (rdsim bench-physics: 2.6-5.3
// instead of 8.0-10.9 per physics step on most JAKA sequences, the deviation from the original work
// within its tolerance).
constexpr double kContactWarmStart = 1.0;

// The robot's model with every movable joint not in spec.ik_joints made fixed at its reset angle, so
// the IK chain moves only ik_joints. Joint indices are unchanged: chain joints still map to robot dofs.
RobotModel ik_model(const RobotModel& robot_model, const Robot& robot, const ReachTaskSpec& spec) {
  RobotModel model = robot_model;
  if (spec.ik_joints.empty() || spec.ik_all_joints) return model;
  for (const std::string& name : spec.ik_joints) {
    const int j = model.joint_index(name);
    if (j < 0 || !model.joints[static_cast<size_t>(j)].movable())
      throw Error(spec.robot_urdf + ": ik_joints names '" + name + "', which is not a movable joint of the robot");
  }
  const Eigen::VectorXf& pose = spec.reset_to_rest ? spec.rest : spec.home;  // where the frozen joints stay
  if (pose.size() != robot.dof())
    throw Error(spec.robot_urdf + ": the " + (spec.reset_to_rest ? "rest" : "home") + " pose has " +
                std::to_string(pose.size()) + " joint values, the robot has " + std::to_string(robot.dof()));
  for (size_t j = 0; j < model.joints.size(); ++j) {
    Joint& joint = model.joints[j];
    if (!joint.movable() || std::find(spec.ik_joints.begin(), spec.ik_joints.end(), joint.name) != spec.ik_joints.end())
      continue;
    const double q = pose[robot.dof_of_joint(static_cast<int>(j))];
    if (joint.type == JointType::Prismatic)
      joint.origin = joint.origin * Eigen::Translation3d(q * joint.axis);
    else
      joint.origin = joint.origin * Eigen::AngleAxisd(q, joint.axis);
    joint.type = JointType::Fixed;
    joint.lower = joint.upper = 0.0;
  }
  return model;
}

}  // namespace

void apply_env_config(const EnvConfig& env, ReachTaskSpec& spec) {
  const ReachOptions& config = env.get<ReachOptions>();
  spec.discrete = env.is_discrete;
  spec.step = static_cast<float>(config.action_step);
  spec.move_noise = static_cast<float>(config.move_noise);
  spec.success_threshold = static_cast<float>(config.success_threshold);
  spec.max_distance = static_cast<float>(config.max_distance);
  spec.workspace_bounds = config.workspace_bounds;
  spec.max_steps = env.max_steps;
  spec.action_repeat = config.action_repeat;
  spec.ik_method = config.ik_method;
  spec.ik_iterations = config.ik_iterations;
  spec.ik_all_joints = config.ik_joints == IkJoints::All;
  spec.reset_to_rest = config.reset_pose == ResetPose::Rest;
  spec.reset_noise = static_cast<float>(config.reset_noise);
  spec.world.solver_iterations = config.solver_iterations;
  // Position motors are pybullet's POSITION_CONTROL as RobotDrlSim called it
  // (setJointMotorControlArray: no speed limit), with pybullet's joint-limit constraints and its
  // default link damping (docs/fidelity.md); the computed-torque drive keeps the limits through its
  // clamped targets instead.
  const bool motors = config.drive == DriveMode::PositionMotor;
  spec.robot.drive = motors ? JointDrive::ConstraintMotor : JointDrive::ComputedTorque;
  spec.robot.limit_constraints = motors;
  spec.robot.motor_speed_limits = !motors;
  spec.robot.link_damping = motors ? kPybulletLinkDamping : 0.0f;
  spec.robot.inertia_from_shapes = motors;  // RobotDrlSim's loadURDF ignored the URDF's inertia tensors
  spec.robot.joint_damping = motors;        // and applied the URDF's joint damping (none in rdsim's Jaka and InMoov)
  if (motors) spec.world = pybullet_solver(spec.world);  // the solver settings pybullet's worlds start with
  // The speed-ups of the original's per-step work (rdsim bench-physics checks them against it):
  // an early exit, joint rows warm-started, and the joints off the IK chain welded while nothing
  // can move them.
  spec.world.solver_residual_threshold = motors ? kResidualThreshold : 0.0;
  spec.world.joint_row_warm_start = motors ? 1.0 : 0.0;
  spec.world.joint_block_solve = motors;
  spec.world.mass_matrix_responses = motors;
  if (motors) spec.world.warmstarting_factor = kContactWarmStart;
  spec.robot.weld_held_joints = motors;
  spec.robot.position_gain = static_cast<float>(config.position_gain);
  spec.robot.velocity_gain = static_cast<float>(config.velocity_gain);
}

RobotModel load_robot_urdf(const ReachTaskSpec& spec) {
  return load_urdf(spec.robot_urdf, UrdfLoadOptions{.search_path = spec.package_paths});
}

ActionSpace ReachTask::action_space() const {
  ActionSpace a;
  a.discrete = spec_.discrete;
  if (spec_.discrete) {
    a.n = 6;
  } else {
    a.low = Eigen::VectorXf::Constant(3, -1.0f);
    a.high = Eigen::VectorXf::Constant(3, 1.0f);
  }
  return a;
}

Eigen::Vector3f ReachTask::move_for(const Action& action) const {
  Eigen::Vector3f d = Eigen::Vector3f::Zero();
  if (spec_.discrete) {
    if (action.index < 0 || action.index > 5)
      throw Error(spec_.name + ": discrete action must be 0..5 (-x, +x, -y, +y, -z, +z), got " +
                  std::to_string(action.index));
    d[action.index / 2] = action.index % 2 ? spec_.step : -spec_.step;
    return d;
  }
  if (action.values.size() != 3)
    throw Error(spec_.name + ": continuous action must have 3 values (dx, dy, dz), got " +
                std::to_string(action.values.size()));
  for (int i = 0; i < 3; ++i) {
    const float v = action.values[i];
    d[i] = spec_.step * (std::isfinite(v) ? std::clamp(v, -1.0f, 1.0f) : 0.0f);
  }
  return d;
}

ReachTask::ReachTask(ReachTaskSpec spec) : spec_(std::move(spec)) {
  if (spec_.target_body >= static_cast<int>(spec_.statics.size()))
    throw Error("ReachTaskSpec: target_body " + std::to_string(spec_.target_body) + " is not a static body");
  if (spec_.rest.size() == 0) spec_.rest = spec_.home;
  world_ = std::make_unique<PhysicsWorld>(spec_.world);
  static_models_.reserve(spec_.statics.size());
  for (const auto& s : spec_.statics) {
    static_models_.push_back(load_urdf(s.urdf));
    static_ids_.push_back(s.free ? world_->add_free_body(static_models_.back(), s.pose)
                                 : world_->add_static_body(static_models_.back(), s.pose, s.free_bodies_only));
  }
  const RobotModel model = load_robot_urdf(spec_);
  robot_ = &world_->add_robot(model, spec_.base_pose, spec_.robot);
  ee_link_ = robot_->model().require_link(spec_.ee_link);
  chain_ = std::make_unique<KinematicChain>(ik_model(robot_->model(), *robot_, spec_), spec_.ee_link);
  const double control_dt = spec_.world.time_step * std::max(spec_.action_repeat, 1);
  max_joint_move_.resize(chain_->dof());
  for (int i = 0; i < chain_->dof(); ++i) {
    chain_dofs_.push_back(robot_->dof_of_joint(chain_->model_joint(i)));
    const double v = robot_->model().joints[static_cast<size_t>(chain_->model_joint(i))].velocity;
    max_joint_move_[i] = v > 0.0 ? v * control_dt : 1e9;
  }
  if (spec_.home.size() != robot_->dof())
    throw Error(spec_.robot_urdf + ": the home pose has " + std::to_string(spec_.home.size()) +
                " joint values, the robot has " + std::to_string(robot_->dof()));
  if (spec_.rest.size() != robot_->dof())
    throw Error(spec_.robot_urdf + ": the rest pose has " + std::to_string(spec_.rest.size()) +
                " joint values, the robot has " + std::to_string(robot_->dof()));
  rest_chain_.resize(chain_->dof());
  for (int i = 0; i < chain_->dof(); ++i) rest_chain_[i] = spec_.rest[chain_dofs_[static_cast<size_t>(i)]];
  base_inverse_ = spec_.base_pose.inverse();
  scratch_q_ = reset_pose();
  robot_->reset_joints(reset_pose());
  // The joints off the IK chain only ever hold their reset pose (RobotOptions::weld_held_joints).
  std::vector<int> held;
  for (int i = 0; i < robot_->dof(); ++i)
    if (std::find(chain_dofs_.begin(), chain_dofs_.end(), i) == chain_dofs_.end()) held.push_back(i);
  robot_->hold(held);
  ee_ = robot_->link_pose(ee_link_).translation();
  set_target(spec_.nominal_target);
}

ReachTask::~ReachTask() = default;

void ReachTask::set_target(const Eigen::Vector3f& point) {
  target_ = point;
  if (spec_.target_body < 0) return;
  Eigen::Isometry3f pose = spec_.statics[static_cast<size_t>(spec_.target_body)].pose;
  pose.translation() = point - pose.linear() * spec_.target_offset;
  const int body = static_ids_[static_cast<size_t>(spec_.target_body)];
  world_->set_static_pose(body, pose);
}

void ReachTask::reset(Rng& rng, bool random_target) {
  scratch_q_ = reset_pose();
  if (spec_.reset_noise > 0.0f)
    for (int dof : chain_dofs_) scratch_q_[dof] += static_cast<float>(rng.uniform(-1.0, 1.0)) * spec_.reset_noise;
  robot_->reset_joints(scratch_q_);
  Eigen::Vector3f target = spec_.nominal_target;
  if (random_target && spec_.random_centre) target = *spec_.random_centre;
  if (random_target)
    for (int i = 0; i < 3; ++i) target[i] += static_cast<float>(rng.uniform(-1.0, 1.0)) * spec_.target_half_range[i];
  set_target(target);
  for (size_t i = 0; i < static_ids_.size(); ++i)  // other free bodies: back in their place, at rest
    if (spec_.statics[i].free && static_cast<int>(i) != spec_.target_body) world_->set_static_pose(static_ids_[i], spec_.statics[i].pose);
  for (int body : static_ids_) world_->forget_contacts(body);
  world_->forget_contacts(robot_->body());
  ee_ = robot_->link_pose(ee_link_).translation();
}

void ReachTask::apply_move(const Eigen::Vector3f& delta, Rng& rng) {
  Eigen::Vector3f goal = ee_ + delta;
  if (spec_.move_noise > 0.0f) {
    const double sigma = static_cast<double>(spec_.move_noise * spec_.step);
    for (int i = 0; i < 3; ++i) goal[i] += static_cast<float>(rng.normal(0.0, sigma));
  }
  const JointVector targets = move_solution(goal);
  for (int i = 0; i < chain_->dof(); ++i)
    robot_->set_position_target(chain_dofs_[static_cast<size_t>(i)], static_cast<float>(targets[i]));
}

Eigen::VectorXf ReachTask::move_targets(const Eigen::Vector3f& delta) const {
  return move_solution(ee_ + delta).cast<float>();
}

JointVector ReachTask::move_solution(Eigen::Vector3f goal) const {
  if (spec_.workspace_bounds) goal = goal.cwiseMax(spec_.workspace.min()).cwiseMin(spec_.workspace.max());
  const Eigen::Vector3d goal_root = (base_inverse_ * goal).cast<double>();
  JointVector q(chain_->dof());
  for (int i = 0; i < chain_->dof(); ++i) q[i] = robot_->joint_position(chain_dofs_[static_cast<size_t>(i)]);
  JointVector solution = q;
  if (spec_.ik_method == IkMethod::NullSpace) {
    NullSpaceIkOptions options;
    options.iterations = spec_.ik_iterations;
    solution = null_space_ik(*chain_, goal_root, q, rest_chain_, options);
  } else if (spec_.effector_orientation) {
    solution = pose_steps(goal_root, solution);
  } else {
    // Damped least squares steps, each one FK + Jacobian (solve_ik's accept/reject test would cost a
    // second FK per iteration; a move of a centimetre or two is well inside the linear regime).
    for (int it = 0; it < spec_.ik_iterations; ++it) {
      ChainJacobian jacobian;
      const Eigen::Vector3d error = goal_root - chain_->forward(solution, jacobian).translation();
      solution = chain_->clamp(solution + damped_least_squares_step(jacobian.topRows<3>(), error, kIkDamping));
    }
  }
  JointVector dq = solution - q;
  if (spec_.robot.drive == JointDrive::ComputedTorque) {
    // This drive closes the whole error within a step (kp 1), so joints it would have to clamp at
    // their speed limit would bend the move; slowing the whole joint step instead keeps the end
    // effector on the requested line. Position motors with a small kp approach their target
    // gradually, as pybullet's do, so they get the IK solution itself.
    double over = 1.0;
    for (int i = 0; i < dq.size(); ++i) over = std::max(over, std::abs(dq[i]) / max_joint_move_[i]);
    dq /= over;
  }
  return q + dq;
}

JointVector ReachTask::pose_steps(const Eigen::Vector3d& goal_root, JointVector q) const {
  const Eigen::Matrix3d orientation = root_orientation();
  for (int it = 0; it < spec_.ik_iterations; ++it) {
    ChainJacobian jacobian;
    const Eigen::Isometry3d tip = chain_->forward(q, jacobian);
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() = goal_root - tip.translation();
    const Eigen::AngleAxisd turn(orientation * tip.linear().transpose());  // tip -> wanted, root frame
    error.tail<3>() = kOrientationWeight * turn.angle() * turn.axis();
    jacobian.bottomRows<3>() *= kOrientationWeight;
    q = chain_->clamp(q + damped_least_squares_step(jacobian, error, kIkDamping));
  }
  return q;
}

Eigen::Matrix3d ReachTask::root_orientation() const {
  return (base_inverse_.linear() * spec_.effector_orientation->toRotationMatrix()).cast<double>();
}

void ReachTask::check_effector_goal(const Eigen::Vector3f& position, const std::string& env) {
  if (!position.allFinite()) throw Error(env + ": effector position must be finite numbers (m)");
}

void ReachTask::check_joint_targets(const Eigen::VectorXf& targets, const std::string& env) const {
  if (targets.size() != robot_->dof())
    throw Error(env + ": expected " + std::to_string(robot_->dof()) + " joint targets (one per joint, in the robot's "
                "joint order), got " + std::to_string(targets.size()));
  if (!targets.allFinite()) throw Error(env + ": joint targets must be finite numbers");
}

RobotInfo ReachTask::robot_info() const {
  RobotInfo info;
  const Robot& robot = *robot_;
  info.robot = robot.model().name;
  info.effector_link = spec_.ee_link;
  info.workspace = spec_.workspace;
  for (int dof = 0; dof < robot.dof(); ++dof) {
    const Joint& j = robot.model().joints[static_cast<size_t>(robot.dof_joint(dof))];
    JointInfo ji;
    ji.name = j.name;
    ji.kind = j.type == JointType::Prismatic ? JointKind::Prismatic
              : j.type == JointType::Continuous ? JointKind::Continuous
                                                : JointKind::Revolute;
    ji.lower = static_cast<float>(j.lower);
    ji.upper = static_cast<float>(j.upper);
    ji.max_velocity = static_cast<float>(j.velocity);
    info.joints.push_back(ji);
  }
  return info;
}

RobotSnapshot ReachTask::robot_snapshot() const {
  const Robot& robot = *robot_;
  RobotSnapshot s;
  s.joint_positions = robot.joint_positions();
  s.joint_velocities = robot.joint_velocities();
  s.joint_targets = robot.position_targets();
  const Eigen::Isometry3f ee = robot.link_pose(ee_link_);
  s.effector_position = ee.translation();
  s.effector_orientation = Eigen::Quaternionf(ee.linear());
  s.target = target_;
  for (int body : static_ids_) {
    const Eigen::Isometry3f pose = world_->static_pose(body);
    s.bodies.push_back({pose.translation(), Eigen::Quaternionf(pose.linear())});
  }
  return s;
}

Eigen::Vector3f ReachTask::ee_velocity() const {
  JointVector q(chain_->dof()), qdot(chain_->dof());
  for (int i = 0; i < chain_->dof(); ++i) {
    q[i] = robot_->joint_position(chain_dofs_[static_cast<size_t>(i)]);
    qdot[i] = robot_->joint_velocity(chain_dofs_[static_cast<size_t>(i)]);
  }
  PositionJacobian jacobian;
  chain_->tip_position(q, jacobian);
  return spec_.base_pose.linear() * (jacobian * qdot).cast<float>();
}

void ReachTask::apply_effector_target(const Eigen::Vector3f& goal) {
  const Eigen::Vector3f clipped = goal.cwiseMax(spec_.workspace.min()).cwiseMin(spec_.workspace.max());
  JointVector q(chain_->dof());
  for (int i = 0; i < chain_->dof(); ++i) q[i] = robot_->joint_position(chain_dofs_[static_cast<size_t>(i)]);
  const Eigen::Vector3d goal_root = (base_inverse_ * clipped).cast<double>();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (spec_.effector_orientation) {
    pose.linear() = root_orientation();
    pose.translation() = goal_root;
  }
  const IkResult ik = spec_.effector_orientation ? solve_ik(*chain_, pose, q) : solve_ik(*chain_, goal_root, q);
  for (int i = 0; i < chain_->dof(); ++i)
    robot_->set_position_target(chain_dofs_[static_cast<size_t>(i)], static_cast<float>(ik.q[i]));
}

void ReachTask::step_physics() {
  for (int k = 0; k < spec_.action_repeat; ++k) world_->step();
  ee_ = robot_->link_pose(ee_link_).translation();
  if (spec_.target_body >= 0 && spec_.statics[static_cast<size_t>(spec_.target_body)].free)
    target_ = world_->static_pose(static_ids_[static_cast<size_t>(spec_.target_body)]) * spec_.target_offset;
}

namespace {

void write_floats(std::ostream& out, const std::vector<float>& v) {
  write_u64(out, v.size());
  for (float x : v) write_f32(out, x);
}

std::vector<float> read_floats(std::istream& in, const std::string& source) {
  std::vector<float> v(read_count(in, 4, source));
  for (float& x : v) x = read_f32(in, source);
  return v;
}

void write_vector3(std::ostream& out, const Eigen::Vector3f& v) {
  for (int i = 0; i < 3; ++i) write_f32(out, v[i]);
}

Eigen::Vector3f read_vector3(std::istream& in, const std::string& source) {
  Eigen::Vector3f v;
  for (int i = 0; i < 3; ++i) v[i] = read_f32(in, source);
  if (!v.allFinite()) throw Error(source + ": env state holds a point that is not finite");
  return v;
}

}  // namespace

void ReachTask::save_state(std::ostream& out) const {
  const RobotState r = robot_->state();
  write_floats(out, r.positions);
  write_floats(out, r.velocities);
  write_floats(out, r.targets);
  write_vector3(out, target_);
  write_vector3(out, ee_);
  write_f64(out, world_->time());
  for (int body : static_ids_)
    if (world_->is_free_body(body)) {
      const FreeBodyState f = world_->free_body_state(body);
      for (float x : f.transform) write_f32(out, x);
      write_vector3(out, f.linear);
      write_vector3(out, f.angular);
    }
}

void ReachTask::load_state(std::istream& in, const std::string& source) {
  RobotState r;
  r.positions = read_floats(in, source);
  r.velocities = read_floats(in, source);
  r.targets = read_floats(in, source);
  const Eigen::Vector3f target = read_vector3(in, source);
  const Eigen::Vector3f ee = read_vector3(in, source);
  const double time = read_f64(in, source);
  if (!(time >= 0.0 && time < 1e12)) throw Error(source + ": env state holds a simulated time out of range");
  std::vector<FreeBodyState> free;
  for (int body : static_ids_)
    if (world_->is_free_body(body)) {
      FreeBodyState f;
      for (float& x : f.transform) x = read_f32(in, source);
      const Eigen::Map<const Eigen::Matrix<float, 3, 3, Eigen::RowMajor>> rotation(f.transform);
      const bool finite = std::all_of(std::begin(f.transform), std::end(f.transform), [](float x) { return std::isfinite(x); });
      if (!finite || !((rotation * rotation.transpose() - Eigen::Matrix3f::Identity()).cwiseAbs().maxCoeff() < 1e-3f))
        throw Error(source + ": env state holds a free body pose that is not finite or not a rotation");
      f.linear = read_vector3(in, source);
      f.angular = read_vector3(in, source);
      free.push_back(f);
    }
  robot_->set_state(r, source);
  set_target(target);  // a free target body: placed at rest, then given its saved motion below
  size_t next = 0;
  for (int body : static_ids_)
    if (world_->is_free_body(body)) world_->set_free_body_state(body, free[next++]);
  ee_ = ee;
  world_->set_time(time);
  drop_caches();
}

bool ReachTask::out_of_bounds() const {
  if (!spec_.workspace_bounds) return false;
  const Eigen::Vector3f m = Eigen::Vector3f::Constant(spec_.workspace_margin);
  const bool outside = (ee_.array() < (spec_.workspace.min() - m).array()).any() ||
                       (ee_.array() > (spec_.workspace.max() + m).array()).any();
  return outside || distance() > spec_.max_distance;
}

bool ReachTask::robot_touches(int static_index) const {
  return world_->touching({robot_->body(), -1}, {static_ids_[static_cast<size_t>(static_index)], -1});
}

}  // namespace rdsim
