#include "rdsim/envs/reach_env.hpp"

#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng_bytes.hpp"

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

// Float32 bounds of the ground-truth observation: target - ee, ee - landmark..., ee,
// link - landmark... (links anywhere within their reach of the robot's base).
ObservationSpace ground_truth_space(const ReachTaskSpec& s, const std::vector<Eigen::Vector3f>& landmarks,
                                   const RobotModel& robot, const std::vector<int>& links) {
  const Eigen::Vector3f lo = s.workspace.min() - Eigen::Vector3f::Constant(s.workspace_margin);
  const Eigen::Vector3f hi = s.workspace.max() + Eigen::Vector3f::Constant(s.workspace_margin);
  const Eigen::Vector3f reach = (hi - lo).cwiseMax(Eigen::Vector3f::Constant(s.max_distance));
  const int n = 3 * (2 + static_cast<int>(landmarks.size()) * (1 + static_cast<int>(links.size())));
  ObservationSpace space;
  space.type = ObsType::Float32;
  space.shape = {n};
  space.low.resize(n);
  space.high.resize(n);
  space.low.head<3>() = -reach;
  space.high.head<3>() = reach;
  for (size_t k = 0; k < landmarks.size(); ++k) {
    const Eigen::Index at = 3 * static_cast<Eigen::Index>(k + 1);
    space.low.segment<3>(at) = lo - landmarks[k];
    space.high.segment<3>(at) = hi - landmarks[k];
  }
  Eigen::Index at = 3 * static_cast<Eigen::Index>(landmarks.size() + 1);
  space.low.segment<3>(at) = lo;
  space.high.segment<3>(at) = hi;
  at += 3;
  const Eigen::Vector3f base = s.base_pose.translation();
  for (int link : links) {
    const Eigen::Vector3f r = Eigen::Vector3f::Constant(link_reach(robot, link));
    for (const Eigen::Vector3f& landmark : landmarks) {
      space.low.segment<3>(at) = base - r - landmark;
      space.high.segment<3>(at) = base + r - landmark;
      at += 3;
    }
  }
  return space;
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
  for (int landmark : terms_.landmarks) {
    check_static_index(task, landmark, "landmark");
    landmark_points_.push_back(task.statics[static_cast<size_t>(landmark)].pose.translation());
  }
  task_ = std::make_unique<ReachTask>(std::move(task));
  for (const std::string& link : terms_.observed_links) observed_links_.push_back(task_->robot_model().require_link(link));
  random_target_ = config.random_target;
  if (!terms_.target_choices.empty()) select_target(terms_.default_choice);

  const ReachTaskSpec& s = task_->spec();
  spec_.env_name = s.name;
  spec_.action = task_->action_space();
  spec_.max_episode_steps = s.max_steps;
  spec_.control_dt = s.world.time_step * s.action_repeat;
  spec_.observation = ground_truth_space(s, landmark_points_, task_->robot_model(), observed_links_);
  if (config.observation == ObservationMode::RawPixels) {
    pixels_ = std::make_unique<PixelView>(*task_, config, terms_.main_view, terms_.second_view);
    spec_.observation = pixels_->space();
  }
  if (config.render_mode == RenderMode::RgbArray) {
    EnvConfig view = config;
    view.image_width = config.render_width;
    view.image_height = config.render_height;
    view.multi_view = false;
    viewer_ = std::make_unique<PixelView>(*task_, view, terms_.main_view, terms_.second_view);
  }
}

void ReachEnv::observe(ObservationOut out) const {
  if (pixels_) {
    pixels_->render(*task_, out.pixels);
    return;
  }
  Eigen::Map<Eigen::VectorXf> o(out.values, spec_.observation.size());
  const Eigen::Vector3f& ee = task_->ee_position();
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
  const bool choices = !terms_.target_choices.empty();
  task_->reset(rng_, random_target_ && !choices);
  if (choices) {
    const auto n = static_cast<std::uint64_t>(terms_.target_choices.size());
    select_target(random_target_ ? static_cast<int>(rng_.below(n)) : terms_.default_choice);
  }
  steps_ = 0;
  done_ = false;
  observe(out);
}

void ReachEnv::select_target(int index) {
  const int n = static_cast<int>(terms_.target_choices.size());
  if (index < 0 || index >= n)
    throw Error(task_->spec().name + ": no target " + std::to_string(index) + " (it has " + std::to_string(n) + ")");
  target_index_ = index;
  task_->set_target(terms_.target_choices[static_cast<size_t>(index)]);
}

StepOutcome ReachEnv::step_into(const Action& action, ObservationOut out) {
  const Eigen::Vector3f move = task_->move_for(action);  // a bad action is an error even after the end
  StepOutcome r;
  if (done_) {
    // Stepping a finished episode: nothing moves, no reward.
    observe(out);
    r.terminated = true;
    return r;
  }
  task_->apply_move(move, rng_);
  task_->step_physics();
  ++steps_;
  observe(out);
  judge(r);
  done_ = r.terminated || r.truncated;
  return r;
}

// Reward, info and episode end of the step just taken (the rules in the header).
void ReachEnv::judge(StepOutcome& r) const {
  const ReachTaskSpec& s = task_->spec();
  const float d = task_->distance();
  r.reward = -d;
  r.info.distance = d;
  r.info.collision = terms_.forbidden_body >= 0 && task_->robot_touches(terms_.forbidden_body);
  const bool pressed = terms_.press_body >= 0 &&
                       task_->world().touching({task_->robot().body(), task_->ee_link()},
                                               {task_->static_body(terms_.press_body), -1});
  r.info.success = !r.info.collision && (task_->reached() || pressed);
  r.info.out_of_bounds = !r.info.success && !r.info.collision && task_->out_of_bounds();
  if (r.info.collision) r.reward = terms_.collision_reward;
  if (r.info.out_of_bounds) r.reward -= s.max_distance * static_cast<float>(s.max_steps - steps_);
  r.terminated = r.info.success || r.info.collision || r.info.out_of_bounds;
  r.truncated = !r.terminated && steps_ >= s.max_steps;
}

namespace {
constexpr std::uint32_t kReachStateTag = 0x45524452;  // "RDRE"
}  // namespace

std::string ReachEnv::save_state() const {
  std::ostringstream out(std::ios::binary);
  write_u32(out, kReachStateTag);
  write_string(out, spec_.env_name);
  write_string(out, rng_to_bytes(rng_));
  write_u32(out, static_cast<std::uint32_t>(steps_));
  write_u32(out, done_ ? 1 : 0);
  write_u32(out, static_cast<std::uint32_t>(target_index_));
  task_->save_state(out);
  return std::move(out).str();
}

void ReachEnv::load_state(const std::string& bytes, const std::string& source) {
  std::istringstream in(bytes, std::ios::binary);
  if (read_u32(in, source) != kReachStateTag) throw Error(source + ": env state is not a reaching env's");
  const std::string name = read_string(in, source);
  if (name != spec_.env_name)
    throw Error(source + ": env state is of " + one_line(name, 40) + ", this env is " + spec_.env_name);
  const Rng rng = rng_from_bytes(read_string(in, source), source);
  const auto steps = static_cast<int>(read_u32(in, source));
  const std::uint32_t done = read_u32(in, source);
  const auto target_index = static_cast<int>(read_u32(in, source));
  const int choices = static_cast<int>(terms_.target_choices.size());
  if (steps < 0 || steps > spec_.max_episode_steps || done > 1 ||
      (choices > 0 ? target_index < 0 || target_index >= choices : target_index != -1))
    throw Error(source + ": env state of " + spec_.env_name + " is damaged (counters out of range)");
  task_->load_state(in, source);
  if (in.peek() != std::char_traits<char>::eof()) throw Error(source + ": env state of " + spec_.env_name + " is damaged (trailing bytes)");
  rng_ = rng;
  steps_ = steps;
  done_ = done != 0;
  target_index_ = target_index;
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
