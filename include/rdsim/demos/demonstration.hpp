#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/core/env.hpp"

// A demonstration: one episode of an env driven by a person (`rdsim teleop`) or by a scripted
// expert (`rdsim demos record --expert`), in the env's own observation and action spaces, so that
// learning from it needs nothing but the env. Files of them: demo_file.hpp.
namespace rdsim {

enum class DemoSource { Scripted, Human };

const char* to_string(DemoSource source);  // "scripted", "human"

struct DemoEpisode {
  DemoSource source = DemoSource::Human;
  // The seed of the reset that started the episode (replaying the actions from a reset with it
  // gives the same observations); none when the env's random stream just continued.
  std::optional<std::uint64_t> seed;
  nlohmann::json env_config = nlohmann::json::object();  // the resolved "env" object it ran with
  std::vector<Observation> observations;  // steps() + 1: the reset's, then the one after each step
  std::vector<Action> actions;            // one per step, in the env's action space
  std::vector<float> rewards;
  std::vector<StepInfo> infos;
  bool terminated = false;  // the last step ended the MDP (success, collision, out of bounds)
  bool truncated = false;   // the last step reached the env's step limit
                            // neither: stopped by the person before the env ended it

  // Starts the episode at the observation of a reset (clears what was recorded).
  void start(Observation first);
  // Appends one env step: the action taken and what the env returned.
  void add(const Action& action, const StepResult& result);

  int steps() const { return static_cast<int>(actions.size()); }
  double episode_return() const;  // undiscounted sum of rewards
  bool success() const;           // info.success on any step
  bool ended() const { return terminated || truncated; }
};

}  // namespace rdsim
