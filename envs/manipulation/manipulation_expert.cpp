#include "rdsim/envs/manipulation/manipulation_expert.hpp"

#include <algorithm>
#include <cmath>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

constexpr float kCube = TaskArea::cube_size;
constexpr float kApproachOpening = kCube + 0.02f;   // m: open this wide around a cube (1 cm each side)
// m: fingers around a cube hold it once their opening is under kHeld and they have stopped closing
// (a cube turned a little on the table stops them a few millimetres wider than its edge).
constexpr float kHeld = kCube + 0.015f;
constexpr float kStopped = 0.0005f;  // m of closing in the last step
constexpr float kFine = 0.5f;                       // the largest action near a cube (2.5 cm at 5 cm per unit)
constexpr float kCentred = 0.006f;                  // m in x and y: close enough above a cube to go down
constexpr float kDownSlack = 0.009f;                // m in x and y: still close enough once down
constexpr float kSqueeze = -1.0f;                   // opening: close with the fingers' whole effort
constexpr float kAbove = 0.06f;                     // m above a cube's centre before going down to it
constexpr float kCarryHeight = 0.08f;               // m: cubes travel at least this high
constexpr float kOnLine = 0.012f;                   // m: close enough to a waypoint in x and y
// m from a pushed cube's centre to the effector behind it: half the cube, half the closed pads' width
// across the push, a little clearance.
constexpr float kPushOffset = kCube / 2.0f + 0.012f;

float xy_distance(const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).head<2>().norm(); }

}  // namespace

ManipulationExpert::ManipulationExpert(Env& env) : env_([&env]() -> ManipulationEnv& {
  auto* m = dynamic_cast<ManipulationEnv*>(&env);
  if (!m) throw Error(env.spec().env_name + ": the manipulation expert drives the manipulation tasks only "
                      "(push, pick_and_place, stack, reach_goal)");
  if (m->spec().action.discrete)
    throw Error(env.spec().env_name + ": the manipulation expert moves the effector by any amount (Box actions): "
                "expected env.is_discrete false");
  return *m;
}()) {}

void ManipulationExpert::reset() {
  stage_ = 0;
  missing_ = false;
  last_opening_ = env_.finger_opening();
  aim_ = env_.world().ee_position();
}

bool ManipulationExpert::grasps() const { return env_.cubes() > 0 && env_.task().name != std::string("push"); }

void ManipulationExpert::miss_first_grasp(const Eigen::Vector2f& offset) {
  if (!grasps())
    throw Error(env_.spec().env_name + ": only a task that grasps a cube (pick_and_place, stack) has a grasp to miss");
  missing_ = true;
  miss_ = offset;
}

Action ManipulationExpert::action(const Eigen::Vector3f& aim, float opening, float largest) {
  aim_ = aim;
  Eigen::Vector3f move = (aim - env_.world().ee_position()) / env_.effector_step();
  const float longest = move.cwiseAbs().maxCoeff();
  if (longest > largest) move *= largest / longest;  // the direction kept
  Eigen::VectorXf a(env_.spec().action.dim());
  const int arm = env_.gripper_blocked() ? static_cast<int>(a.size()) : static_cast<int>(a.size()) - 1;
  if (env_.control() == ArmControl::Joints) {
    // The same effector move as the joint moves the env's IK would make for it, all scaled down
    // together when one exceeds joint_step (the effector's path kept).
    const Eigen::VectorXf targets = env_.world().move_targets(move * env_.effector_step());
    for (int i = 0; i < arm; ++i)
      a[i] = (targets[i] - env_.world().robot().joint_position(env_.world().chain_dofs()[static_cast<size_t>(i)])) /
             env_.joint_step();
    const float over = a.head(arm).cwiseAbs().maxCoeff();
    if (over > 1.0f) a.head(arm) /= over;
  } else {
    a.head<3>() = move;
  }
  if (!env_.gripper_blocked())
    a[arm] = opening < 0.0f ? kSqueeze : std::clamp(2.0f * opening / env_.finger_stroke() - 1.0f, -1.0f, 1.0f);
  return Action::continuous(a);
}

Action ManipulationExpert::act() {
  const Action a = plan();
  last_opening_ = env_.finger_opening();
  return a;
}

Action ManipulationExpert::plan() {
  const std::string& task = env_.task().name;
  if (env_.cubes() == 0) return action(env_.goals()[0], kSqueeze);
  if (task == std::string("push")) return push();
  if (env_.cubes() == 1) return carry(0, env_.goals()[0]);
  // stack: the first cube onto its goal, let go and rise, then the second on top.
  const float low = env_.world().spec().workspace.min().z();
  const Eigen::Vector3f ee = env_.world().ee_position();
  if (stage_ == 0 && (env_.cube_position(0) - env_.goals()[0]).norm() < kOnLine) stage_ = 1;
  if (stage_ == 1) {
    if (env_.finger_opening() < kApproachOpening - 0.004f) return action(ee, kApproachOpening);  // open in place
    if (ee.z() < env_.cube_position(0).z() + kAbove - 0.01f)
      return action(Eigen::Vector3f(ee.x(), ee.y(), std::max(low, env_.cube_position(0).z() + kAbove)), kApproachOpening);
    stage_ = 2;
  }
  return stage_ == 0 ? carry(0, env_.goals()[0]) : carry(1, env_.goals()[1]);
}

Action ManipulationExpert::carry(int k, const Eigen::Vector3f& goal) {
  const Eigen::Vector3f ee = env_.world().ee_position();
  Eigen::Vector3f cube = env_.cube_position(k);
  const float low = env_.world().spec().workspace.min().z();
  if (missing_) {
    // The grasp to miss is over once the fingers have closed past the cube's width, down beside it.
    if (env_.finger_opening() < kCube - 0.005f && ee.z() < std::max(cube.z(), low) + 0.01f &&
        last_opening_ - env_.finger_opening() < kStopped)
      missing_ = false;
    else
      cube.head<2>() += miss_;  // aim at the point beside the cube as if the cube were there
  }
  const bool around = !missing_ && xy_distance(cube, ee) < 0.02f && std::abs(cube.z() - ee.z()) < 0.025f;
  const float opening = env_.finger_opening();
  if (around && opening < kHeld && last_opening_ - opening < kStopped) {
    // Held: move the effector by what the cube still has to go, travelling high when it is far.
    Eigen::Vector3f aim = ee + (goal - cube);
    if (xy_distance(goal, cube) > 0.02f) {
      // Far from the goal: up to the carrying height first (clear of the other cube), then across.
      aim.z() = std::max(aim.z(), ee.z() + (kCarryHeight - cube.z()));
      if (cube.z() < kCarryHeight - 0.01f) aim.head<2>() = ee.head<2>();
    }
    // Off the table gently: a jerk would shake the cube in the fingers.
    return action(aim, kSqueeze, cube.z() < kCube ? kFine : 1.0f);
  }
  const float grasp_z = std::max(cube.z(), low);
  const Eigen::Vector3f at_cube(cube.x(), cube.y(), grasp_z);
  // Once down beside the cube, a few millimetres off (an arm that drifts as it descends) are
  // corrected on the way down instead of by going back up.
  const bool down = ee.z() < cube.z() + kCube && xy_distance(cube, ee) < kDownSlack;
  if (xy_distance(cube, ee) > kCentred && !down) {
    // Above the cube first: up and over when low beside it, so the fingers never land on it.
    const Eigen::Vector3f above(cube.x(), cube.y(), cube.z() + kAbove);
    if (ee.z() < cube.z() + kCube) return action(Eigen::Vector3f(ee.x(), ee.y(), above.z()), kApproachOpening, kFine);
    return action(above, kApproachOpening, xy_distance(cube, ee) < 0.03f ? kFine : 1.0f);
  }
  if (ee.z() > grasp_z + 0.006f) return action(at_cube, kApproachOpening, kFine);
  return action(at_cube, kSqueeze, kFine);
}

Action ManipulationExpert::push() {
  const Eigen::Vector3f ee = env_.world().ee_position();
  const Eigen::Vector3f cube = env_.cube_position(0);
  const Eigen::Vector3f goal = env_.goals()[0];
  const float low = env_.world().spec().workspace.min().z();
  Eigen::Vector3f to_goal = goal - cube;
  to_goal.z() = 0.0f;
  const float remaining = to_goal.norm();
  if (remaining < 1e-3f) return action(ee, kSqueeze);
  const Eigen::Vector3f u = to_goal / remaining;
  Eigen::Vector3f behind = cube - u * kPushOffset;
  behind.z() = low;
  Eigen::Vector3f rel = ee - cube;
  rel.z() = 0.0f;
  const float along = rel.dot(u);
  const float lateral = (rel - along * u).norm();
  const bool low_enough = ee.z() < low + 0.01f;
  if (low_enough && along < -0.02f && lateral < 0.01f) {
    Eigen::Vector3f aim = goal - u * kPushOffset;  // where the effector stands once the cube is there
    aim.z() = low;
    return action(aim, kSqueeze);
  }
  if (xy_distance(ee, behind) < 0.01f) return action(behind, kSqueeze);  // down behind the cube
  const Eigen::Vector3f above = behind + Eigen::Vector3f(0.0f, 0.0f, kAbove);
  // Up first when low near the cube, so the way round does not sweep it along.
  if (low_enough && rel.norm() < 0.06f) return action(Eigen::Vector3f(ee.x(), ee.y(), above.z()), kSqueeze);
  return action(above, kSqueeze);
}

}  // namespace rdsim
