#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/demos/demo_writer.hpp"
#include "rdsim/demos/demonstration.hpp"

// What a person does to an env in `rdsim teleop`, without the window: episodes, the env's own
// actions (what demonstrations record), the RobotControl moves of the original's sliders, and
// recording. The window (teleop_window.hpp) only turns keys, sliders and buttons into these calls,
// so everything here is tested without a display. The env is in-process or an `rdsim serve`
// session: the session sees only Env and RobotControl.
namespace rdsim {

// The six moves of the reaching envs' Discrete(6) space, in its order: -x, +x, -y, +y, -z, +z.
enum class Move { MinusX, PlusX, MinusY, PlusY, MinusZ, PlusZ };

// The env action for a move: Discrete(6): its index; Box(3): a full step (1) along its axis; Box(4)
// (the manipulation tasks: moves and the fingers): that, with `gripper` as the fingers' value (-1
// closed, 1 open). rdsim::Error for other action spaces.
Action move_action(Move move, const ActionSpace& space, float gripper = 1.0f);

struct TeleopStatus {
  int steps = 0;                 // env steps in this episode
  double episode_return = 0.0;
  float last_reward = 0.0f;
  StepInfo info;                 // of the last step (distance, success, collision, out of bounds);
                                 // after a reset: the distance from the start, nothing else set
  bool ended = false;            // terminated or truncated: Reset starts the next episode
  bool terminated = false, truncated = false;
  bool recording = false;
  int recorded_steps = 0;        // of the demonstration being recorded
  long long saved_episodes = 0;  // in the demonstration file (all of it, when appending)
  std::string message;           // what the last button did ("saved episode 3: 42 steps, success")
  bool has_gripper = false;      // the actions hold the fingers' opening (Box(4))
  bool gripper_open = true;      // what the keys ask of the fingers (each episode starts open)
};

class TeleopSession {
public:
  // `env` must also be a RobotControl (rdsim::Error otherwise). Episode k (0-based) starts from
  // reset(seed + k). `writer`, when given, receives every recorded episode; `env_config` is the
  // env's resolved "env" object (recorded with each episode). Resets the env.
  TeleopSession(Env& env, std::uint64_t seed, DemoWriter* writer, nlohmann::json env_config);

  Env& env() { return env_; }
  RobotControl& control() { return control_; }
  const TeleopStatus& status() const { return status_; }
  bool can_record() const { return writer_ != nullptr; }

  // A new episode (the next seed). A demonstration being recorded is discarded.
  void reset();
  // One env step with an action of the env's own space: recorded while recording. Nothing
  // happens once the episode has ended (returns false).
  bool act(const Action& action);
  // The key moves and the gripper key as env actions (the gripper as status().gripper_open says).
  bool act(Move move);
  // Opens a closed gripper or closes an open one: one env step without a move. False when the
  // episode is over; rdsim::Error for an env whose actions have no fingers.
  bool toggle_gripper();
  // One env step by RobotControl (the original's sliders). Not while recording: demonstrations
  // hold the env's own actions (rdsim::Error). Nothing happens once the episode has ended.
  bool move_effector(const Eigen::Vector3f& position);
  bool set_joint_targets(const Eigen::VectorXf& targets);

  // Starts a demonstration at a fresh reset (its seed is recorded), so that every demonstration
  // starts where an env episode starts. rdsim::Error without a demonstration file.
  void start_recording();
  // Saves the demonstration so far (nothing without a step); it ends "stopped" unless the env ended it.
  void stop_recording();
  void discard_recording();

private:
  void after_step(const StepResult& r);
  void save();

  Env& env_;
  RobotControl& control_;
  DemoWriter* writer_;
  nlohmann::json env_config_;
  std::uint64_t next_seed_;
  std::uint64_t episode_seed_ = 0;
  DemoEpisode recording_;
  TeleopStatus status_;
};

}  // namespace rdsim
