#include "rdsim/envs/manipulation/manipulation_env.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/episode_state.hpp"
#include "rdsim/envs/manipulation/gripper_arm.hpp"
#include "rdsim/envs/randomization.hpp"
#include "rdsim/envs/reaching/reach_arm.hpp"

namespace rdsim {
namespace {

constexpr int kPerCube = 16;  // position 3, quaternion 4, linear 3, angular 3, relative position 3
constexpr float kMaxSpeed = 10.0f;  // m/s: bound of the velocities observed
constexpr float kMaxSpin = 100.0f;  // rad/s
constexpr float kReach = 1.0f;      // m: positions are bounded by the workspace box grown by this
constexpr std::uint32_t kStateTag = 0x4d4e4452;  // "RDNM"

void set3(ObservationSpace& s, int at, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  s.low.segment<3>(at) = lo;
  s.high.segment<3>(at) = hi;
}

// Bounds of the observed joint positions (control: joints): their limits, or +-4 pi for a joint
// without (continuous).
constexpr float kTurns = 4.0f * 3.14159265f;

// The Float32 bounds of the layout in the header; `joints` the observed arm joints' limits (none
// with effector control).
ObservationSpace observation_space(const Eigen::AlignedBox3f& workspace, bool blocked, int cubes, int points, float stroke,
                                   const std::vector<std::pair<float, float>>& joints) {
  const Eigen::Vector3f lo = workspace.min() - Eigen::Vector3f::Constant(kReach);
  const Eigen::Vector3f hi = workspace.max() + Eigen::Vector3f::Constant(kReach);
  const Eigen::Vector3f span = hi - lo;
  const Eigen::Vector3f speed = Eigen::Vector3f::Constant(kMaxSpeed), spin = Eigen::Vector3f::Constant(kMaxSpin);
  const int observed = 6 + (blocked ? 0 : 1) + static_cast<int>(joints.size()) + kPerCube * cubes;
  ObservationSpace s;
  s.type = ObsType::Float32;
  s.shape = {observed + 6 * points};
  s.low.resize(s.shape[0]);
  s.high.resize(s.shape[0]);
  int at = 0;
  set3(s, at, lo, hi);
  set3(s, at + 3, -speed, speed);
  at += 6;
  if (!blocked) {
    s.low[at] = 0.0f;
    s.high[at] = stroke;
    ++at;
  }
  for (const auto& [lower, upper] : joints) {
    s.low[at] = std::isfinite(lower) ? lower : -kTurns;
    s.high[at] = std::isfinite(upper) ? upper : kTurns;
    ++at;
  }
  for (int k = 0; k < cubes; ++k, at += kPerCube) {
    set3(s, at, lo, hi);
    s.low.segment<4>(at + 3).setConstant(-1.0f);
    s.high.segment<4>(at + 3).setConstant(1.0f);
    set3(s, at + 7, -speed, speed);
    set3(s, at + 10, -spin, spin);
    set3(s, at + 13, -span, span);
  }
  for (int p = 0; p < 2 * points; ++p, at += 3) set3(s, at, lo, hi);
  s.parts = {{"effector_position", 3}, {"effector_velocity", 3}};
  if (!blocked) s.parts.push_back({"finger_opening", 1});
  if (!joints.empty()) s.parts.push_back({"joint_positions", static_cast<int>(joints.size())});
  for (int k = 1; k <= cubes; ++k) {
    const std::string cube = "cube" + std::to_string(k) + "_";
    s.parts.insert(s.parts.end(), {{cube + "position", 3},
                                   {cube + "orientation", 4},
                                   {cube + "velocity", 3},
                                   {cube + "angular_velocity", 3},
                                   {cube + "from_effector", 3}});
  }
  s.parts.insert(s.parts.end(), {{"achieved_goal", 3 * points}, {"desired_goal", 3 * points}});
  return s;
}

void put3(float* at, const Eigen::Vector3f& v) { std::copy_n(v.data(), 3, at); }

float clipped(float v) { return std::isfinite(v) ? std::clamp(v, -1.0f, 1.0f) : 0.0f; }

}  // namespace

EnvConfig manipulation_env_config(const std::string& name, ManipulationOptions options) {
  EnvConfig c{.name = name, .is_discrete = false, .max_steps = 50};
  // The repo's JAKA with its gripper: the effector (between the pads) 15 cm above the task area's
  // centre, the gripper pointing straight down, its fingers closing along the world's y axis (the
  // IK's solution for that pose, to 0.1 mm and 1 mrad).
  ArmOptions arm{.effector_link = "gripper_tcp",
                 .home_pose = {-0.2561, 1.4791, -1.7509, 1.8426, 1.5708, 1.3147},
                 .workspace_min = {0.2, -0.35, 0.025},
                 .workspace_max = {0.75, 0.35, 0.35}};
  arm.has_target = false;
  c.options = {EnvOptions(std::move(options)), EnvOptions(std::move(arm)), EnvOptions(RandomizeOptions{})};
  return c;
}

ManipulationEnv::ManipulationEnv(const ManipulationTask& task, const EnvConfig& config) : task_(task) {
  const ManipulationOptions& o = config.get<ManipulationOptions>();
  if (config.is_discrete && (!o.block_gripper || o.control == ArmControl::Joints))
    throw Error("env.is_discrete: " + config.name + " with " + (o.block_gripper ? "control \"joints\"" : "the fingers to move") +
                " has Box actions only (Discrete(6) are the effector's moves with the gripper blocked: reach_goal, push): "
                "expected false");
  GripperArmScene scene = gripper_arm_scene(config, task);
  area_ = scene.area;
  finger_dofs_ = scene.finger_dofs;
  finger_lower_ = scene.finger_lower;
  for (size_t f = 0; f < finger_dofs_.size(); ++f) stroke_ += scene.finger_upper[f] - scene.finger_lower[f];
  for (size_t f = 0; f < finger_dofs_.size(); ++f) finger_share_.push_back((scene.finger_upper[f] - scene.finger_lower[f]) / stroke_);
  blocked_ = o.block_gripper;
  effector_step_ = static_cast<float>(o.effector_step);
  control_ = o.control;
  joint_step_ = static_cast<float>(o.joint_step);
  world_ = std::make_unique<ReachTask>(std::move(scene.spec));
  std::vector<std::pair<float, float>> joint_limits;  // the observed arm joints (control: joints)
  if (control_ == ArmControl::Joints)
    for (int dof : world_->chain_dofs()) {
      const Joint& j = world_->robot_model().joints[static_cast<size_t>(world_->robot().dof_joint(dof))];
      const float none = std::numeric_limits<float>::infinity();
      joint_limits.emplace_back(j.type == JointType::Continuous ? -none : static_cast<float>(j.lower),
                                j.type == JointType::Continuous ? none : static_cast<float>(j.upper));
    }
  for (int k = 0; k < task_.cubes; ++k)
    world_->world().set_free_body_friction(world_->static_body(first_cube_index + k), static_cast<float>(o.object_friction));
  for (int link = 0; link < static_cast<int>(world_->robot_model().links.size()); ++link) {
    const int joint = world_->robot_model().links[static_cast<size_t>(link)].parent_joint;
    const int dof = joint >= 0 ? world_->robot().dof_of_joint(joint) : -1;
    if (std::find(finger_dofs_.begin(), finger_dofs_.end(), dof) != finger_dofs_.end())
      world_->robot().set_link_friction(link, static_cast<float>(o.finger_friction));
  }

  const int points = std::max(task_.cubes, 1);
  spec_.env_name = config.name;
  if (config.is_discrete) {
    spec_.action = world_->action_space();  // Discrete(6): -x, +x, -y, +y, -z, +z by effector_step
  } else {
    spec_.action.discrete = false;
    const int arm_values = control_ == ArmControl::Joints ? static_cast<int>(world_->chain_dofs().size()) : 3;
    spec_.action.low = Eigen::VectorXf::Constant(arm_values + (blocked_ ? 0 : 1), -1.0f);
    spec_.action.high = Eigen::VectorXf::Constant(arm_values + (blocked_ ? 0 : 1), 1.0f);
  }
  spec_.max_episode_steps = config.max_steps;
  spec_.control_dt = o.physics_step * o.substeps;
  spec_.observation = observation_space(world_->spec().workspace, blocked_, task_.cubes, points, stroke_, joint_limits);
  spec_.goal.observation = spec_.observation.size() - 6 * points;
  spec_.goal.points = points;
  spec_.goal.distance_threshold = static_cast<float>(o.distance_threshold);
  spec_.goal.reward = o.reward_type;
  goals_.assign(static_cast<size_t>(points), Eigen::Vector3f::Zero());
  const Eigen::AlignedBox3f& w = world_->spec().workspace;
  if (config.observation == ObservationMode::RawPixels) {
    pixels_ = std::make_unique<PixelView>(*world_, config, arm_main_view(w), arm_second_view(w));
    spec_.observation = pixel_goal_space(pixels_->space(), spec_.observation, spec_.goal);
  }
  if (config.render_mode == RenderMode::RgbArray) {
    EnvConfig view = config;
    view.image_width = config.render_width;
    view.image_height = config.render_height;
    view.multi_view = false;
    view.image_channels = "rgb";  // frames for people
    viewer_ = std::make_unique<PixelView>(*world_, view, arm_main_view(w), arm_second_view(w));
  }
  renderer_backend_ = config.renderer;
  camera_mounts_ = {world_camera("scene", arm_main_view(w))};
  robot_info_ = world_->robot_info();
  for (const CameraMount& m : camera_mounts_) robot_info_.cameras.push_back({m.name, m.link, m.fov_deg});
  const auto* randomize = config.find<RandomizeOptions>();
  randomizer_ = std::make_unique<TaskRandomizer>(*world_, randomize ? randomize->randomize : Randomization{}, 2);
}

ManipulationEnv::~ManipulationEnv() = default;

Eigen::Vector3f ManipulationEnv::cube_position(int cube) const {
  return world_->world().static_pose(world_->static_body(first_cube_index + cube)).translation();
}

float ManipulationEnv::finger_opening() const {
  float opening = 0.0f;
  for (size_t f = 0; f < finger_dofs_.size(); ++f) opening += world_->robot().joint_position(finger_dofs_[f]) - finger_lower_[f];
  return opening;
}

void ManipulationEnv::set_opening(float opening) {
  for (size_t f = 0; f < finger_dofs_.size(); ++f)
    world_->robot().set_position_target(finger_dofs_[f], finger_lower_[f] + finger_share_[f] * opening);
}

void ManipulationEnv::achieved_goal(float* out) const {
  if (task_.cubes == 0) {
    put3(out, world_->ee_position());
    return;
  }
  for (int k = 0; k < task_.cubes; ++k) put3(out + 3 * k, cube_position(k));
}

void ManipulationEnv::observe(ObservationOut out) const {
  if (pixels_) {
    pixels_->render(*world_, out);
    observe_goals(out.values);
    return;
  }
  float* o = out.values;
  const Eigen::Vector3f& ee = world_->ee_position();
  put3(o, ee);
  put3(o + 3, world_->ee_velocity());
  int at = 6;
  if (!blocked_) o[at++] = finger_opening();
  if (control_ == ArmControl::Joints)
    for (int dof : world_->chain_dofs()) o[at++] = world_->robot().joint_position(dof);
  const PhysicsWorld& physics = world_->world();
  for (int k = 0; k < task_.cubes; ++k, at += kPerCube) {
    const int body = world_->static_body(first_cube_index + k);
    const Eigen::Isometry3f pose = physics.static_pose(body);
    Eigen::Quaternionf q(pose.linear());
    if (q.w() < 0.0f) q.coeffs() = -q.coeffs();
    const FreeBodyState motion = physics.free_body_state(body);
    put3(o + at, pose.translation());
    std::copy_n(q.coeffs().data(), 4, o + at + 3);  // x, y, z, w
    put3(o + at + 7, motion.linear);
    put3(o + at + 10, motion.angular);
    put3(o + at + 13, pose.translation() - ee);
  }
  const ObservationSpace& s = spec_.observation;
  Eigen::Map<Eigen::VectorXf> head(o, at);
  head = head.cwiseMax(s.low.head(at)).cwiseMin(s.high.head(at));
  observe_goals(o);
}

void ManipulationEnv::observe_goals(float* values) const {
  const GoalLayout& g = spec_.goal;
  achieved_goal(values + g.achieved_offset());
  for (size_t p = 0; p < goals_.size(); ++p) put3(values + g.desired_offset() + 3 * static_cast<int>(p), goals_[p]);
  const ObservationSpace& s = spec_.observation;
  const int at = g.achieved_offset(), n = 2 * g.goal_size();
  Eigen::Map<Eigen::VectorXf> goals(values + at, n);
  goals = goals.cwiseMax(s.low.segment(at, n)).cwiseMin(s.high.segment(at, n));
}

void ManipulationEnv::judge(const float* observation, StepOutcome& r) const {
  const GoalLayout& g = spec_.goal;
  const float* achieved = observation + g.achieved_offset();
  const float* desired = observation + g.desired_offset();
  float d2 = 0.0f;
  for (int i = 0; i < g.goal_size(); ++i) d2 += (achieved[i] - desired[i]) * (achieved[i] - desired[i]);
  r.info.distance = std::sqrt(d2);
  r.info.success = g.is_success(achieved, desired);
  r.reward = g.reward_of(achieved, desired);
  r.terminated = r.info.success;
  r.truncated = !r.terminated && steps_ >= spec_.max_episode_steps;
}

void ManipulationEnv::place(const Placement& placement) {
  if (static_cast<int>(placement.cubes.size()) != task_.cubes || placement.goals.size() != goals_.size())
    throw Error(spec_.env_name + ": the task drew " + std::to_string(placement.cubes.size()) + " cubes and " +
                std::to_string(placement.goals.size()) + " goals");  // a task's bug, not the user's
  PhysicsWorld& physics = world_->world();
  for (int k = 0; k < task_.cubes; ++k)
    physics.set_static_pose(world_->static_body(first_cube_index + k),
                            Eigen::Isometry3f(Eigen::Translation3f(placement.cubes[static_cast<size_t>(k)])));
  placed_ = placement.cubes;
  goals_ = placement.goals;
  show_goals();
}

void ManipulationEnv::show_goals() {
  const int first_marker = first_cube_index + task_.cubes;
  for (size_t p = 0; p < goals_.size(); ++p)
    world_->world().set_static_pose(world_->static_body(first_marker + static_cast<int>(p)),
                                    Eigen::Isometry3f(Eigen::Translation3f(goals_[p])));
}

Placement ManipulationEnv::draw_placement(Rng& rng) const {
  Placement placement = task_.draw(area_, rng);
  for (Eigen::Vector3f& cube : placement.cubes) cube += randomizer_->placement(0);
  for (Eigen::Vector3f& goal : placement.goals) goal += randomizer_->placement(1);
  return placement;
}

std::vector<bool> ManipulationEnv::unmoved_cubes() const {
  constexpr float kUnmoved = 1e-3f;  // m: a resting cube settles by less
  std::vector<bool> unmoved;
  for (int k = 0; k < task_.cubes; ++k)
    unmoved.push_back(placed_.size() == static_cast<size_t>(task_.cubes) &&
                      (cube_position(k) - placed_[static_cast<size_t>(k)]).norm() < kUnmoved);
  return unmoved;
}

bool ManipulationEnv::goal_point_reached() const {
  std::vector<float> achieved(static_cast<size_t>(spec_.goal.goal_size()));
  achieved_goal(achieved.data());
  for (size_t p = 0; p < goals_.size(); ++p)
    if ((Eigen::Map<const Eigen::Vector3f>(&achieved[3 * p]) - goals_[p]).norm() < spec_.goal.distance_threshold) return true;
  return false;
}

bool ManipulationEnv::redraw_unmoved(Rng& rng, ObservationOut out) {
  RDSIM_ASSERT(!done_, "redraw_unmoved within an episode");
  constexpr float kApart = 1.5f * TaskArea::cube_size;  // m between cube centres in x and y (draw_cubes')
  constexpr float kClear = 0.10f;                       // m from the effector in x and y: clear of the open fingers
  constexpr int kTries = 100;
  const auto planar = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).head<2>().norm(); };
  const std::vector<bool> unmoved = unmoved_cubes();
  const bool keep_goal = goal_point_reached();  // what the demonstrator has done stays
  if (keep_goal && std::find(unmoved.begin(), unmoved.end(), true) == unmoved.end()) {
    observe(out);
    return false;
  }
  std::vector<Eigen::Vector3f> cubes;
  for (int k = 0; k < task_.cubes; ++k) cubes.push_back(cube_position(k));
  const Eigen::Vector3f ee = world_->ee_position();
  for (int t = 0; t < kTries; ++t) {
    const Placement fresh = draw_placement(rng);
    std::vector<Eigen::Vector3f> next = cubes;
    for (size_t k = 0; k < next.size(); ++k)
      if (unmoved[k]) next[k] = fresh.cubes[k];
    bool clear = true;
    for (size_t k = 0; k < next.size(); ++k) {
      if (!unmoved[k]) continue;
      clear = clear && planar(next[k], ee) >= kClear;
      for (size_t j = 0; j < next.size(); ++j) clear = clear && (j == k || planar(next[k], next[j]) >= kApart);
    }
    if (!clear) continue;
    for (size_t k = 0; k < next.size(); ++k) {
      if (!unmoved[k]) continue;
      world_->world().set_static_pose(world_->static_body(first_cube_index + static_cast<int>(k)),
                                      Eigen::Isometry3f(Eigen::Translation3f(next[k])));
      placed_[k] = next[k];  // still unmoved
    }
    if (!keep_goal) {
      goals_ = fresh.goals;
      show_goals();
    }
    observe(out);
    return true;
  }
  observe(out);  // no clear layout in kTries draws: everything stays
  return false;
}

Observation ManipulationEnv::reset(std::optional<std::uint64_t> seed) { return reset_through_into(*this, seed); }

StepResult ManipulationEnv::step(const Action& action) { return step_through_into(*this, action); }

void ManipulationEnv::reset_into(ObservationOut out, std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  randomizer_->reset(seed);
  if (pixels_) randomizer_->apply(*pixels_);
  world_->reset(rng_, false);
  place(draw_placement(rng_));
  steps_ = 0;
  done_ = false;
  observe(out);
}

StepOutcome ManipulationEnv::step_into(const Action& action, ObservationOut out) {
  if (spec_.action.discrete) {
    const Eigen::Vector3f move = world_->move_for(action);  // checks the index, an error even after the episode's end
    return control_step(out, [&] { world_->apply_move(move, rng_); });
  }
  const int n = spec_.action.dim();
  const int arm = blocked_ ? n : n - 1;  // values for the arm; then the fingers'
  if (action.values.size() != n)  // an error even after the episode's end
    throw Error(spec_.env_name + ": expected an action of " + std::to_string(n) + " values (" +
                (control_ == ArmControl::Joints ? std::to_string(arm) + " joint moves" : std::string("dx, dy, dz")) +
                (blocked_ ? "" : ", fingers") + "), got " + std::to_string(action.values.size()));
  return control_step(out, [&] {
    if (control_ == ArmControl::Joints) {
      Robot& robot = world_->robot();
      for (int i = 0; i < arm; ++i) {
        const int dof = world_->chain_dofs()[static_cast<size_t>(i)];
        robot.set_position_target(dof, robot.joint_position(dof) + clipped(action.values[i]) * joint_step_);
      }
    } else {
      const Eigen::Vector3f move(clipped(action.values[0]), clipped(action.values[1]), clipped(action.values[2]));
      world_->apply_move(move * effector_step_, rng_);
    }
    if (!blocked_) set_opening((clipped(action.values[arm]) + 1.0f) / 2.0f * stroke_);
  });
}

template <class SetTargets>
StepOutcome ManipulationEnv::control_step(ObservationOut out, SetTargets&& set_targets) {
  StepOutcome r;
  if (done_) {
    observe(out);
    r.terminated = true;
    return r;
  }
  set_targets();
  world_->step_physics();
  ++steps_;
  observe(out);
  judge(out.values, r);
  done_ = r.terminated || r.truncated;
  return r;
}

RobotSnapshot ManipulationEnv::robot_state() {
  RobotSnapshot s = world_->robot_snapshot();
  s.target = goals_.front();
  s.steps = steps_;
  return s;
}

StepResult ManipulationEnv::move_effector(const Eigen::Vector3f& position) {
  ReachTask::check_effector_goal(position, spec_.env_name);
  return step_result(spec_.observation,
                     [&](ObservationOut out) { return control_step(out, [&] { world_->apply_effector_target(position); }); });
}

StepResult ManipulationEnv::set_joint_targets(const Eigen::VectorXf& targets) {
  world_->check_joint_targets(targets, spec_.env_name);
  return step_result(spec_.observation, [&](ObservationOut out) {
    return control_step(out, [&] { world_->robot().set_position_targets(targets); });
  });
}

void ManipulationEnv::camera_image(int camera, int width, int height, Image& out) {
  if (!cameras_) cameras_ = std::make_unique<RobotCameras>(*world_, camera_mounts_, renderer_backend_);
  cameras_->render(*world_, camera, width, height, out);
}

bool ManipulationEnv::step_physics_only() {
  world_->step_physics();
  return true;
}

bool ManipulationEnv::render(Image& frame) {
  if (!viewer_) return false;
  viewer_->render(*world_, frame.rgb);
  frame.width = static_cast<int>(viewer_->space().shape[1]);
  frame.height = static_cast<int>(viewer_->space().shape[0]);
  return true;
}

std::string ManipulationEnv::save_state() const {
  std::ostringstream out(std::ios::binary);
  write_episode_header(out, kStateTag, spec_.env_name, rng_, steps_, done_);
  for (const Eigen::Vector3f& g : goals_)
    for (int i = 0; i < 3; ++i) write_f32(out, g[i]);
  world_->save_state(out);
  if (randomizer_->active()) randomizer_->save(out);
  return std::move(out).str();
}

void ManipulationEnv::load_state(const std::string& bytes, const std::string& source) {
  std::istringstream in(bytes, std::ios::binary);
  const EpisodeCounters header =
      read_episode_header(in, kStateTag, "a manipulation env's", spec_.env_name, spec_.max_episode_steps, source);
  Placement placement;
  for (size_t p = 0; p < goals_.size(); ++p) {
    Eigen::Vector3f g;
    for (int i = 0; i < 3; ++i) g[i] = read_f32(in, source);
    if (!g.allFinite()) throw Error(source + ": env state of " + spec_.env_name + " is damaged (a goal is not finite)");
    placement.goals.push_back(g);
  }
  world_->load_state(in, source);
  if (randomizer_->active()) randomizer_->load(in, source);
  if (in.peek() != std::char_traits<char>::eof()) throw Error(source + ": env state of " + spec_.env_name + " is damaged (trailing bytes)");
  rng_ = header.rng;
  steps_ = header.steps;
  done_ = header.done;
  goals_ = placement.goals;
  placed_.clear();
  show_goals();
}

}  // namespace rdsim
