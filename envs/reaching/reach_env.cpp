#include "rdsim/envs/reaching/reach_env.hpp"

#include <algorithm>
#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/episode_state.hpp"

namespace rdsim {
namespace {

// How far link `link`'s frame origin can be from the robot's root: the joint offsets on the way
// there, end to end (a bound whatever the joint angles).
float link_reach(const RobotModel& model, int link) {
  double reach = 0.0;
  for (int j = model.links[static_cast<size_t>(link)].parent_joint; j >= 0;) {
    const Joint& joint = model.joints[static_cast<size_t>(j)];
    reach += joint.origin.translation().norm();
    j = model.links[static_cast<size_t>(joint.parent_link)].parent_joint;
  }
  return static_cast<float>(reach);
}

// Where the end effector can be: the workspace box plus margin with workspace_bounds, else anywhere
// within its reach of the robot's base.
Eigen::AlignedBox3f ee_box(const ReachTaskSpec& s, const RobotModel& robot, int ee_link) {
  if (!s.workspace_bounds) {
    const Eigen::Vector3f base = s.base_pose.translation();
    const Eigen::Vector3f r = Eigen::Vector3f::Constant(link_reach(robot, ee_link));
    return Eigen::AlignedBox3f(base - r, base + r);
  }
  return Eigen::AlignedBox3f(s.workspace.min() - Eigen::Vector3f::Constant(s.workspace_margin),
                             s.workspace.max() + Eigen::Vector3f::Constant(s.workspace_margin));
}

// Float32 bounds of the ground-truth observation (the layouts in reach_env.hpp): full = target - ee,
// ee - landmark..., ee, link - landmark... (links anywhere within their reach of the robot's base);
// relative = ee - target, ee - landmark.... A landmark may move by up to `slack` from its point.
ObservationSpace ground_truth_space(const ReachTaskSpec& s, const Eigen::AlignedBox3f& ee,
                                   const std::vector<Eigen::Vector3f>& landmarks,
                                   const std::vector<Eigen::Vector3f>& slack, const RobotModel& robot,
                                   const std::vector<int>& links, ObservationLayout layout) {
  const bool full = layout == ObservationLayout::Full;
  const Eigen::Vector3f lo = ee.min(), hi = ee.max();
  const Eigen::Vector3f reach = (hi - lo).cwiseMax(Eigen::Vector3f::Constant(s.max_distance));
  const int per_landmark = full ? 1 + static_cast<int>(links.size()) : 1;
  const int n = 3 * ((full ? 2 : 1) + static_cast<int>(landmarks.size()) * per_landmark);
  ObservationSpace space;
  space.type = ObsType::Float32;
  space.shape = {n};
  space.low.resize(n);
  space.high.resize(n);
  space.low.head<3>() = -reach;
  space.high.head<3>() = reach;
  for (size_t k = 0; k < landmarks.size(); ++k) {
    const Eigen::Index at = 3 * static_cast<Eigen::Index>(k + 1);
    space.low.segment<3>(at) = lo - landmarks[k] - slack[k];
    space.high.segment<3>(at) = hi - landmarks[k] + slack[k];
  }
  if (!full) return space;
  Eigen::Index at = 3 * static_cast<Eigen::Index>(landmarks.size() + 1);
  space.low.segment<3>(at) = lo;
  space.high.segment<3>(at) = hi;
  at += 3;
  const Eigen::Vector3f base = s.base_pose.translation();
  for (int link : links) {
    const Eigen::Vector3f r = Eigen::Vector3f::Constant(link_reach(robot, link));
    for (size_t k = 0; k < landmarks.size(); ++k) {
      space.low.segment<3>(at) = base - r - landmarks[k] - slack[k];
      space.high.segment<3>(at) = base + r - landmarks[k] + slack[k];
      at += 3;
    }
  }
  return space;
}

// The names of ground_truth_space's values (reach_env.hpp).
std::vector<ObservationPart> ground_truth_parts(const ReachTerms& terms, ObservationLayout layout) {
  const bool full = layout == ObservationLayout::Full;
  std::vector<ObservationPart> parts{{full ? "target_from_effector" : "effector_from_target", 3}};
  for (const ReachTerms::Landmark& l : terms.landmarks) parts.push_back({"effector_from_" + l.name, 3});
  if (!full) return parts;
  parts.push_back({"effector_position", 3});
  for (const std::string& link : terms.observed_links)
    for (const ReachTerms::Landmark& l : terms.landmarks) parts.push_back({link + "_from_" + l.name, 3});
  return parts;
}

void check_static_index(const ReachTaskSpec& s, int index, const char* what) {
  if (index < -1 || index >= static_cast<int>(s.statics.size()))
    throw Error(s.name + ": " + what + " " + std::to_string(index) + " is not one of its " +
                std::to_string(s.statics.size()) + " static bodies");
}

}  // namespace

ReachEnv::ReachEnv(ReachTaskSpec task, ReachTerms terms, const EnvConfig& config) : terms_(std::move(terms)) {
  check_static_index(task, terms_.press_body, "press body");
  check_static_index(task, terms_.forbidden_body, "forbidden body");
  check_static_index(task, terms_.walking_body, "walking body");
  std::vector<Eigen::Vector3f> slack;  // how far each landmark can move from its point
  for (const ReachTerms::Landmark& landmark : terms_.landmarks) {
    check_static_index(task, landmark.body, "landmark");
    landmark_points_.push_back(task.statics[static_cast<size_t>(landmark.body)].pose.translation());
    const float walk = landmark.body == terms_.walking_body ? terms_.walk_range : 0.0f;
    slack.emplace_back(walk, walk, 0.0f);
  }
  task_ = std::make_unique<ReachTask>(std::move(task));
  for (const std::string& link : terms_.observed_links) observed_links_.push_back(task_->robot_model().require_link(link));
  const ReachOptions& options = config.get<ReachOptions>();
  random_target_ = options.random_target;
  layout_ = options.observation_layout;
  end_on_success_ = options.end_on_success;
  if (!terms_.target_choices.empty()) select_target(terms_.default_choice);

  const ReachTaskSpec& s = task_->spec();
  spec_.env_name = s.name;
  spec_.action = task_->action_space();
  spec_.max_episode_steps = s.max_steps;
  spec_.control_dt = s.world.time_step * s.action_repeat;
  spec_.observation = ground_truth_space(s, ee_box(s, task_->robot_model(), task_->ee_link()), landmark_points_,
                                         slack, task_->robot_model(), observed_links_, layout_);
  spec_.observation.parts = ground_truth_parts(terms_, layout_);
  if (config.observation == ObservationMode::RawPixels) {
    pixels_ = std::make_unique<PixelView>(*task_, config, terms_.main_view, terms_.second_view);
    spec_.observation = pixels_->space();
  }
  if (config.render_mode == RenderMode::RgbArray) {
    EnvConfig view = config;
    view.image_width = config.render_width;
    view.image_height = config.render_height;
    view.multi_view = false;
    view.image_channels = "rgb";  // frames for people
    viewer_ = std::make_unique<PixelView>(*task_, view, terms_.main_view, terms_.second_view);
  }
  renderer_backend_ = config.renderer;
  robot_info_ = task_->robot_info();
  // The task's first-person cameras, and the main view fixed in the world to watch the whole task.
  terms_.cameras.push_back(world_camera("scene", terms_.main_view));
  for (const CameraMount& m : terms_.cameras) {
    if (!m.link.empty()) task_->robot_model().require_link(m.link);
    robot_info_.cameras.push_back({m.name, m.link, m.fov_deg});
  }
  const auto* randomize = config.find<RandomizeOptions>();
  randomizer_ = std::make_unique<TaskRandomizer>(*task_, randomize ? randomize->randomize : Randomization{}, 1);
}

ReachEnv::~ReachEnv() = default;

void ReachEnv::observe(ObservationOut out) const {
  if (pixels_) {
    pixels_->render(*task_, out);
    return;
  }
  Eigen::Map<Eigen::VectorXf> o(out.values, spec_.observation.size());
  const Eigen::Vector3f& ee = task_->ee_position();
  if (layout_ == ObservationLayout::Relative) {
    o.head<3>() = ee - task_->target();
    for (size_t k = 0; k < landmark_points_.size(); ++k)
      o.segment<3>(3 * static_cast<Eigen::Index>(k + 1)) = ee - landmark_points_[k];
    return;
  }
  o.head<3>() = task_->target() - ee;
  for (size_t k = 0; k < landmark_points_.size(); ++k)
    o.segment<3>(3 * static_cast<Eigen::Index>(k + 1)) = ee - landmark_points_[k];
  Eigen::Index at = 3 * static_cast<Eigen::Index>(landmark_points_.size() + 1);
  o.segment<3>(at) = ee;
  at += 3;
  for (int link : observed_links_) {
    const Eigen::Vector3f p = task_->robot().link_pose(link).translation();
    for (const Eigen::Vector3f& landmark : landmark_points_) {
      o.segment<3>(at) = p - landmark;
      at += 3;
    }
  }
}

// The plain interface through the "into" one: one implementation of the episode rules.
Observation ReachEnv::reset(std::optional<std::uint64_t> seed) { return reset_through_into(*this, seed); }

StepResult ReachEnv::step(const Action& action) { return step_through_into(*this, action); }

void ReachEnv::reset_into(ObservationOut out, std::optional<std::uint64_t> seed) {
  if (seed) rng_.reseed(*seed);
  randomizer_->reset(seed);
  if (terms_.walking_body >= 0) {
    walk_offset_.setZero();
    place_walking_body();
  }
  const bool choices = !terms_.target_choices.empty();
  task_->reset(rng_, random_target_ && !choices);
  if (choices) {
    const auto n = static_cast<std::uint64_t>(terms_.target_choices.size());
    select_target(random_target_ ? static_cast<int>(rng_.below(n)) : terms_.default_choice);
  }
  apply_randomizer(true);
  steps_ = 0;
  done_ = false;
  observe(out);
}

void ReachEnv::apply_randomizer(bool new_episode) {
  if (!randomizer_->active()) return;
  const Eigen::Vector3f offset = randomizer_->placement(0);
  if (new_episode && !offset.isZero()) task_->set_target(task_->target() + offset);
  if (pixels_) randomizer_->apply(*pixels_);
}

void ReachEnv::select_target(int index) {
  const int n = static_cast<int>(terms_.target_choices.size());
  if (index < 0 || index >= n)
    throw Error(task_->spec().name + ": no target " + std::to_string(index) + " (it has " + std::to_string(n) + ")");
  target_index_ = index;
  task_->set_target(terms_.target_choices[static_cast<size_t>(index)]);
}

template <class SetTargets>
StepOutcome ReachEnv::control_step(ObservationOut out, SetTargets&& set_targets) {
  StepOutcome r;
  if (done_) {
    // Stepping a finished episode: nothing moves, no reward.
    observe(out);
    r.terminated = true;
    return r;
  }
  walk();
  set_targets();
  task_->step_physics();
  ++steps_;
  observe(out);
  judge(r);
  done_ = r.terminated || r.truncated;
  return r;
}

void ReachEnv::walk() {
  if (terms_.walking_body < 0) return;
  for (int i = 0; i < 2; ++i) {
    const float move = static_cast<float>(rng_.uniform(-1.0, 1.0)) * terms_.walk_step;
    walk_offset_[i] = std::clamp(walk_offset_[i] + move, -terms_.walk_range, terms_.walk_range);
  }
  place_walking_body();
}

void ReachEnv::place_walking_body() {
  const int index = terms_.walking_body;
  Eigen::Isometry3f pose = task_->spec().statics[static_cast<size_t>(index)].pose;
  pose.translation().head<2>() += walk_offset_;
  task_->world().set_static_pose(task_->static_body(index), pose);
  for (size_t k = 0; k < terms_.landmarks.size(); ++k)
    if (terms_.landmarks[k].body == index) landmark_points_[k] = pose.translation();
}

StepOutcome ReachEnv::step_into(const Action& action, ObservationOut out) {
  const Eigen::Vector3f move = task_->move_for(action);  // a bad action is an error even after the end
  return control_step(out, [&] { task_->apply_move(move, rng_); });
}

StepResult ReachEnv::move_effector(const Eigen::Vector3f& position) {
  ReachTask::check_effector_goal(position, spec_.env_name);
  return step_result(spec_.observation,
                     [&](ObservationOut out) { return control_step(out, [&] { task_->apply_effector_target(position); }); });
}

StepResult ReachEnv::set_joint_targets(const Eigen::VectorXf& targets) {
  task_->check_joint_targets(targets, spec_.env_name);
  return step_result(spec_.observation, [&](ObservationOut out) {
    return control_step(out, [&] { task_->robot().set_position_targets(targets); });
  });
}

RobotSnapshot ReachEnv::robot_state() {
  RobotSnapshot s = task_->robot_snapshot();
  s.steps = steps_;
  return s;
}

void ReachEnv::camera_image(int camera, int width, int height, Image& out) {
  if (!cameras_) cameras_ = std::make_unique<RobotCameras>(*task_, terms_.cameras, renderer_backend_);
  cameras_->render(*task_, camera, width, height, out);
}

// Reward, info and episode end of the step just taken (the rules in the header).
void ReachEnv::judge(StepOutcome& r) const {
  const ReachTaskSpec& s = task_->spec();
  const float d = task_->distance();
  r.info.distance = d;
  r.info.collision = terms_.forbidden_body >= 0 && task_->robot_touches(terms_.forbidden_body);
  const bool pressed = terms_.press_body >= 0 &&
                       task_->world().touching({task_->robot().body(), task_->ee_link()},
                                               {task_->static_body(terms_.press_body), -1});
  const bool at_goal = !r.info.collision && (task_->reached() || pressed);
  const bool last = steps_ >= s.max_steps;
  r.info.success = at_goal && (end_on_success_ || last);
  r.info.out_of_bounds = !at_goal && !r.info.collision && task_->out_of_bounds();
  const bool negative_distance = terms_.reward == RewardRule::NegativeDistance;
  if (negative_distance) {
    r.reward = r.info.collision ? terms_.collision_reward : -d;
  } else {
    r.reward = 1.0f / std::max(d, 0.01f) - 2.0f * static_cast<float>(steps_) / static_cast<float>(s.max_steps);
    if (r.info.collision) r.reward -= 10.0f;
    if (d < 0.1f) r.reward += 10.0f;
  }
  if (r.info.out_of_bounds) r.reward -= s.max_distance * static_cast<float>(s.max_steps - steps_);
  r.terminated = (end_on_success_ && r.info.success) || (r.info.collision && negative_distance) || r.info.out_of_bounds;
  r.truncated = !r.terminated && last;
}

namespace {
constexpr std::uint32_t kReachStateTag = 0x45524452;  // "RDRE"
}  // namespace

std::string ReachEnv::save_state() const {
  std::ostringstream out(std::ios::binary);
  write_episode_header(out, kReachStateTag, spec_.env_name, rng_, steps_, done_);
  write_u32(out, static_cast<std::uint32_t>(target_index_));
  write_f32(out, walk_offset_.x());  // m, the walking body's offset from its place (0 without one)
  write_f32(out, walk_offset_.y());
  task_->save_state(out);
  if (randomizer_->active()) randomizer_->save(out);
  return std::move(out).str();
}

void ReachEnv::load_state(const std::string& bytes, const std::string& source) {
  std::istringstream in(bytes, std::ios::binary);
  const EpisodeCounters header =
      read_episode_header(in, kReachStateTag, "a reaching env's", spec_.env_name, spec_.max_episode_steps, source);
  const auto target_index = static_cast<int>(read_u32(in, source));
  const float walk_x = read_f32(in, source);  // two statements: argument order is unspecified
  const float walk_y = read_f32(in, source);
  const Eigen::Vector2f walk_offset(walk_x, walk_y);
  const int choices = static_cast<int>(terms_.target_choices.size());
  if (choices > 0 ? target_index < 0 || target_index >= choices : target_index != -1)
    throw Error(source + ": env state of " + spec_.env_name + " is damaged (counters out of range)");
  const float walk_range = terms_.walking_body >= 0 ? terms_.walk_range : 0.0f;
  if (!walk_offset.allFinite() || walk_offset.cwiseAbs().maxCoeff() > walk_range)
    throw Error(source + ": env state of " + spec_.env_name + " is damaged (walking body offset out of range)");
  task_->load_state(in, source);
  if (randomizer_->active()) randomizer_->load(in, source);
  if (in.peek() != std::char_traits<char>::eof()) throw Error(source + ": env state of " + spec_.env_name + " is damaged (trailing bytes)");
  apply_randomizer(false);
  rng_ = header.rng;
  steps_ = header.steps;
  done_ = header.done;
  target_index_ = target_index;
  walk_offset_ = walk_offset;
  if (terms_.walking_body >= 0) place_walking_body();
}

bool ReachEnv::step_physics_only() {
  task_->step_physics();
  return true;
}

bool ReachEnv::render(Image& frame) {
  if (!viewer_) return false;
  viewer_->render(*task_, frame.rgb);
  frame.width = static_cast<int>(viewer_->space().shape[1]);
  frame.height = static_cast<int>(viewer_->space().shape[0]);
  return true;
}

}  // namespace rdsim
