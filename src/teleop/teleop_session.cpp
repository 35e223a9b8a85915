#include "rdsim/teleop/teleop_session.hpp"

#include <cstdio>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

RobotControl& robot_control(Env& env) {
  auto* control = dynamic_cast<RobotControl*>(&env);
  if (!control)
    throw Error("env " + env.spec().env_name + " cannot be driven by hand (it has no robot: RobotControl); "
                "the reaching envs can");
  return *control;
}

std::string describe_end(const DemoEpisode& e) {
  const char* how = e.success() ? "success" : e.terminated ? "ended by the env" : e.truncated ? "step limit" : "stopped";
  char text[96];
  std::snprintf(text, sizeof text, "%d steps, return %.2f, %s", e.steps(), e.episode_return(), how);
  return text;
}

}  // namespace

Action move_action(Move move, const ActionSpace& space, float gripper) {
  const int index = static_cast<int>(move);
  if (space.discrete && space.n == 6) return Action::discrete(index);
  if (!space.discrete && (space.dim() == 3 || space.dim() == 4)) {
    Eigen::VectorXf v = Eigen::VectorXf::Zero(space.dim());
    v[index / 2] = index % 2 ? 1.0f : -1.0f;
    if (space.dim() == 4) v[3] = gripper;
    return Action::continuous(std::move(v));
  }
  throw Error("the keyboard moves need Discrete(6), Box(3) or Box(4) actions (the reaching and manipulation envs')");
}

bool TeleopSession::act(Move move) {
  return act(move_action(move, env_.spec().action, status_.gripper_open ? 1.0f : -1.0f));
}

bool TeleopSession::toggle_gripper() {
  if (!status_.has_gripper)
    throw Error("env " + env_.spec().env_name + " has no gripper in its actions (the manipulation tasks with Box(4) do)");
  if (status_.ended) return false;
  status_.gripper_open = !status_.gripper_open;
  Eigen::VectorXf v = Eigen::VectorXf::Zero(4);
  v[3] = status_.gripper_open ? 1.0f : -1.0f;
  return act(Action::continuous(std::move(v)));
}

TeleopSession::TeleopSession(Env& env, std::uint64_t seed, DemoWriter* writer, nlohmann::json env_config)
    : env_(env), control_(robot_control(env)), writer_(writer), env_config_(std::move(env_config)), next_seed_(seed) {
  if (writer_) status_.saved_episodes = writer_->episodes();
  reset();
  status_.message.clear();
}

void TeleopSession::reset() {
  if (status_.recording) {
    status_.recording = false;
    status_.recorded_steps = 0;
  }
  episode_seed_ = next_seed_++;
  const Observation first = env_.reset(episode_seed_);
  recording_.start(first);
  const long long saved = status_.saved_episodes;
  status_ = TeleopStatus{};
  status_.saved_episodes = saved;
  const ActionSpace& space = env_.spec().action;
  status_.has_gripper = !space.discrete && space.dim() == 4;
  // The distance to the target from the start, before any step (the task's distance: effector to target).
  const RobotSnapshot start = control_.robot_state();
  status_.info.distance = (start.effector_position - start.target).norm();
  status_.message = "new episode (seed " + std::to_string(episode_seed_) + ")";
}

void TeleopSession::after_step(const StepResult& r) {
  ++status_.steps;
  status_.last_reward = r.reward;
  status_.episode_return += r.reward;
  status_.info = r.info;
  status_.terminated = r.terminated;
  status_.truncated = r.truncated;
  status_.ended = r.terminated || r.truncated;
  if (status_.ended && !status_.recording)
    status_.message = r.info.success ? "success: press Reset for a new episode" : "episode over: press Reset";
}

bool TeleopSession::act(const Action& action) {
  if (status_.ended) return false;
  const StepResult r = env_.step(action);
  if (status_.recording) {
    recording_.add(action, r);
    status_.recorded_steps = recording_.steps();
  }
  after_step(r);
  if (status_.recording && status_.ended) save();  // the env ended the demonstration
  return true;
}

bool TeleopSession::move_effector(const Eigen::Vector3f& position) {
  if (status_.recording) throw Error("while recording, drive with the env's own actions (keys), not the sliders");
  if (status_.ended) return false;
  after_step(control_.move_effector(position));
  return true;
}

bool TeleopSession::set_joint_targets(const Eigen::VectorXf& targets) {
  if (status_.recording) throw Error("while recording, drive with the env's own actions (keys), not the sliders");
  if (status_.ended) return false;
  after_step(control_.set_joint_targets(targets));
  return true;
}

void TeleopSession::start_recording() {
  if (!writer_) throw Error("no demonstration file to record into (rdsim teleop --record FILE)");
  reset();
  recording_.source = DemoSource::Human;
  recording_.seed = episode_seed_;
  recording_.env_config = env_config_;
  status_.recording = true;
  status_.message = "recording episode " + std::to_string(status_.saved_episodes + 1) + " (seed " +
                    std::to_string(episode_seed_) + ")";
}

void TeleopSession::stop_recording() {
  if (!status_.recording) return;
  if (recording_.steps() == 0) {
    discard_recording();
    status_.message = "nothing recorded (no step)";
    return;
  }
  save();
}

void TeleopSession::discard_recording() {
  if (!status_.recording) return;
  status_.recording = false;
  status_.message = "discarded " + std::to_string(recording_.steps()) + " recorded steps";
  status_.recorded_steps = 0;
  recording_.start(recording_.observations.front());
}

void TeleopSession::save() {
  status_.recording = false;
  writer_->append(recording_);
  status_.saved_episodes = writer_->episodes();
  status_.message = "saved episode " + std::to_string(status_.saved_episodes) + ": " + describe_end(recording_) + " -> " +
                    writer_->path();
  status_.recorded_steps = 0;
}

}  // namespace rdsim
