#include "rdsim/envs/manipulation/gripper_arm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rdsim/core/data_dir.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/suggest.hpp"
#include "rdsim/envs/arm_joints.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/manipulation/manipulation_options.hpp"
#include "rdsim/sim/kinematics.hpp"

namespace rdsim {
namespace {

// A little more than a cube: fingers must open at least this wide (m) to close around one.
constexpr float kCubeClearance = 0.005f;
// The table (assets/objects/table.urdf, top at z = 0) stands centred here; the floor under it.
const Eigen::Vector3f kTableCentre(0.35f, 0.0f, 0.0f);
constexpr float kFloorHeight = -0.75f;
// Damped-least-squares steps (position and orientation) per move: a move of a few centimetres from
// the current joints is well inside the linear regime.
constexpr int kIkIterations = 4;
// The share of their error the joints' drive closes per physics step: 0.3 with the default 10
// physics steps of an env step, 97 % of a move within it; with other substeps the gain that closes
// as much per env step (1 - 0.7^(10 / substeps)). With 1, which closes it all in one physics step,
// the joints ran into their effort limits and overshot: a 2 cm move straight down ended 1.5 cm to
// the side.
float position_gain(int substeps) { return static_cast<float>(1.0 - std::pow(0.7, 10.0 / substeps)); }
// The solver per physics step: Bullet's sequential-impulse iterations over the contacts of the
// pads, cubes and table and the fingers' motor, limit and coupling rows. Up to kShortStep (the
// default 10 physics steps of 4 ms) 10 iterations. A longer step moves a closing finger further
// into a cube before its contact stops it, and the iterations then leave the fingers' rows and the
// contacts disagreeing: with 4 steps of 10 ms and 10 iterations the Panda's expert grasped in 58 %
// of pick_and_place and 35 % of stack episodes (200 seeds), and with 40 and an early exit a held
// cube jittered out of the JAKA's pads (14 mm in 5 s). So with longer steps the fingers' rows are
// solved directly first, from last step's impulses (WorldSettings::joint_row_warm_start and
// joint_block_solve), and the iterations, up to 40, stop once an iteration changes no velocity by
// more than sqrt(1e-5) m/s: the Panda's 99 % and 97 %, a slip of 0.3 mm, most steps a few
// iterations (tests/envs/test_manipulation.cpp, docs/benchmarks.md).
constexpr double kShortStep = 0.004;  // s
constexpr int kShortStepIterations = 10, kLongStepIterations = 40;
constexpr double kLongStepResidual = 1e-5;  // m^2/s^2

void set_solver(double physics_step, WorldSettings& world) {
  const bool long_step = physics_step > kShortStep * (1.0 + 1e-9);
  world.solver_iterations = long_step ? kLongStepIterations : kShortStepIterations;
  world.solver_residual_threshold = long_step ? kLongStepResidual : 0.0;
  world.joint_row_warm_start = long_step ? 1.0 : 0.0;
  world.joint_block_solve = long_step;
  // The fingers' rows take their responses from the arm drive's own M(q) (one factorisation per
  // physics step) instead of an articulated-body pass per row: about 10 % of a push step at the default
  // substeps (WorldSettings::mass_matrix_responses).
  world.mass_matrix_responses = true;
}

std::string point_text(const Eigen::Vector3f& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", p.x(), p.y(), p.z());
  return text;
}

std::string joint_names(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// The robot dof (movable joints in model order) of model joint `joint`.
int dof_of(const RobotModel& model, int joint) {
  int dof = 0;
  for (int j = 0; j < joint; ++j) dof += model.joints[static_cast<size_t>(j)].movable() ? 1 : 0;
  return dof;
}

// The finger joints (checked) into `scene`.
void add_fingers(const RobotModel& model, const std::vector<std::string>& fingers, const std::vector<int>& path,
                 const std::string& urdf, GripperArmScene& scene) {
  std::vector<std::string> prismatic;
  for (const Joint& j : model.joints)
    if (j.type == JointType::Prismatic) prismatic.push_back(j.name);
  float stroke = 0.0f;
  for (const std::string& name : fingers) {
    const int j = model.joint_index(name);
    const std::string key = urdf + ": env.finger_joints: \"" + one_line(name, 60) + "\" ";
    if (j < 0)
      throw Error(key + "is not a joint of the robot" + did_you_mean(name, prismatic) + " (its prismatic joints: " +
                  (prismatic.empty() ? std::string("none") : joint_names(prismatic)) + ")");
    const Joint& joint = model.joints[static_cast<size_t>(j)];
    if (joint.type != JointType::Prismatic) throw Error(key + "is not a prismatic joint (fingers slide)");
    if (std::find(path.begin(), path.end(), j) != path.end())
      throw Error(key + "is on the arm's path to the effector link (a finger moves beside it)");
    const int dof = dof_of(model, j);
    if (std::find(scene.finger_dofs.begin(), scene.finger_dofs.end(), dof) != scene.finger_dofs.end())
      throw Error(key + "is listed twice");
    if (!(joint.effort > 0.0)) throw Error(key + "has no effort limit in the URDF (<limit effort>): the fingers could not grip");
    scene.finger_dofs.push_back(dof);
    scene.finger_lower.push_back(static_cast<float>(joint.lower));
    scene.finger_upper.push_back(static_cast<float>(joint.upper));
    stroke += static_cast<float>(joint.upper - joint.lower);
  }
  if (stroke < TaskArea::cube_size + kCubeClearance) {
    char text[160];
    std::snprintf(text, sizeof text, "the fingers open %.4f m at most (the sum of their strokes): they cannot close "
                  "around a %.2f m cube", stroke, TaskArea::cube_size);
    throw Error(urdf + ": env.finger_joints: " + text);
  }
}

// rdsim::Error naming `key` when the box lo..hi leaves the workspace box (the effector's reach).
void check_inside(const Eigen::AlignedBox3f& workspace, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                  const char* key, const std::string& what) {
  if (workspace.contains(lo) && workspace.contains(hi)) return;
  throw Error(std::string("env.") + key + ": " + what + " " + point_text(lo) + " .. " + point_text(hi) +
              " reach outside the workspace box " + point_text(workspace.min()) + " .. " +
              point_text(workspace.max()) + " (workspace_min, workspace_max)");
}

// The cubes' starts and the goals must lie where the effector can go: x and y inside the workspace
// box, and the highest goal under its top (a cube resting on the table is grasped from above, its
// centre may lie under the box's floor).
void check_area(const GripperArmScene& scene, const ManipulationTask& task) {
  const TaskArea& a = scene.area;
  Eigen::AlignedBox3f w = scene.spec.workspace;
  const float low = w.min().z();
  const Eigen::Vector3f c(a.centre.x(), a.centre.y(), low);
  if (task.cubes > 0) {
    const Eigen::Vector3f r(a.object_range, a.object_range, 0.0f);
    check_inside(w, c - r, c + r, "object_range", "the cubes' starts (area_centre +- object_range)");
  }
  const float rise = task.cubes > 1 ? TaskArea::cube_size * static_cast<float>(task.cubes - 1) : a.goal_height;
  const float top = (task.cubes > 0 ? TaskArea::cube_size / 2.0f : low) + rise;
  const Eigen::Vector3f r(a.goal_range, a.goal_range, 0.0f);
  check_inside(w, c - r, c + r + Eigen::Vector3f(0.0f, 0.0f, std::max(top - low, 0.0f)),
               a.goal_height > 0.0f ? "goal_height" : "goal_range", "the goals (area_centre +- goal_range, up to goal_height)");
}

}  // namespace

GripperArmScene gripper_arm_scene(const EnvConfig& config, const ManipulationTask& task) {
  const ArmOptions& arm = config.get<ArmOptions>();
  const ManipulationOptions& o = config.get<ManipulationOptions>();
  const std::string assets = repo_root() + "/assets";
  GripperArmScene scene;
  ReachTaskSpec& s = scene.spec;
  s.name = config.name;
  const RobotModel model =
      apply_arm_options(arm, arm.urdf.empty() ? assets + "/jaka/jaka_zu7_gripper.urdf" : arm.urdf, s);
  add_fingers(model, o.finger_joints, path_joints(model, model.link_index(arm.effector_link)), s.robot_urdf, scene);
  for (size_t f = 0; f < scene.finger_dofs.size(); ++f)  // open, or closed with a blocked gripper
    s.home[scene.finger_dofs[f]] = o.block_gripper ? scene.finger_lower[f] : scene.finger_upper[f];

  // The gripper keeps the home pose's orientation.
  const std::vector<Eigen::Isometry3d> links = link_poses(model, s.home.cast<double>());
  const int ee = model.link_index(arm.effector_link);
  const Eigen::Isometry3f ee_home = s.base_pose * links[static_cast<size_t>(ee)].cast<float>();
  s.effector_orientation = Eigen::Quaternionf(ee_home.linear());
  s.workspace = Eigen::AlignedBox3f(vector3(arm.workspace_min), vector3(arm.workspace_max));
  if (!(s.workspace.min().array() < s.workspace.max().array()).all())
    throw Error("env.workspace_max: expected each value above workspace_min's");
  constexpr float margin = 0.03f;  // m, as the reaching tasks allow
  if (s.workspace.exteriorDistance(ee_home.translation()) > margin)
    throw Error(s.robot_urdf + ": env.home_pose puts " + s.ee_link + " at " + point_text(ee_home.translation()) +
                ", outside the workspace box " + point_text(s.workspace.min()) + " .. " +
                point_text(s.workspace.max()) + " (workspace_min, workspace_max)");

  s.statics = {{assets + "/objects/table.urdf", Eigen::Isometry3f(Eigen::Translation3f(kTableCentre))},
               {assets + "/objects/floor.urdf", Eigen::Isometry3f(Eigen::Translation3f(0.0f, 0.0f, kFloorHeight)),
                false, true}};
  static const char* const colours[] = {"blue", "green"};
  if (task.cubes > 2) throw Error(config.name + ": at most 2 cubes");
  const Eigen::Isometry3f aside(Eigen::Translation3f(kTableCentre.x(), kTableCentre.y(), TaskArea::cube_size / 2));
  for (int k = 0; k < task.cubes; ++k)
    s.statics.push_back({assets + "/objects/cube_" + colours[k] + ".urdf", aside, true});
  for (int k = 0; k < std::max(task.cubes, 1); ++k)
    s.statics.push_back({assets + "/objects/goal_marker_" + colours[k] + ".urdf", Eigen::Isometry3f::Identity()});

  s.discrete = config.is_discrete;  // ManipulationEnv allows it with the gripper blocked and effector control
  s.step = static_cast<float>(o.effector_step);
  s.move_noise = 0.0f;
  s.workspace_bounds = true;
  s.max_steps = config.max_steps;
  s.action_repeat = o.substeps;
  s.ik_iterations = kIkIterations;
  s.reset_noise = 0.0f;  // every episode starts from the home pose (panda-gym's)
  s.world.time_step = o.physics_step;
  set_solver(o.physics_step, s.world);
  s.robot.position_gain = position_gain(o.substeps);
  s.robot.motor_dofs = scene.finger_dofs;  // the fingers squeeze with their effort
  for (size_t f = 1; f < scene.finger_dofs.size(); ++f)  // and move as one (a gripper's linkage)
    s.robot.coupled_dofs.emplace_back(scene.finger_dofs[0], scene.finger_dofs[f]);

  scene.area.centre = Eigen::Vector2f(static_cast<float>(o.area_centre[0]), static_cast<float>(o.area_centre[1]));
  scene.area.object_range = static_cast<float>(o.object_range);
  scene.area.goal_range = static_cast<float>(o.goal_range);
  scene.area.goal_height = static_cast<float>(o.goal_height);
  scene.area.lowest_effector = s.workspace.min().z();
  check_area(scene, task);
  return scene;
}

}  // namespace rdsim
