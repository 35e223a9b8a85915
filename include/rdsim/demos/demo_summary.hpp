#pragma once
#include "rdsim/demos/demo_file.hpp"

// What `rdsim demos info` prints about a demonstration file.
namespace rdsim {

struct DemoSummary {
  int episodes = 0;
  int scripted = 0, human = 0;  // episodes by source
  long long steps = 0;
  double success_rate = 0.0;    // share of episodes with info.success on some step
  double mean_return = 0.0;     // undiscounted
  double mean_length = 0.0;     // steps per episode
  int terminated = 0, truncated = 0, stopped = 0;  // how episodes ended
  int collisions = 0;           // episodes with info.collision on some step
};

DemoSummary summarize(const DemoFile& demos);

}  // namespace rdsim
