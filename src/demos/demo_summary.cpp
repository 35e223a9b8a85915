#include "rdsim/demos/demo_summary.hpp"

namespace rdsim {

DemoSummary summarize(const DemoFile& demos) {
  DemoSummary s;
  double returns = 0.0;
  int successes = 0;
  for (const DemoEpisode& e : demos.episodes) {
    ++s.episodes;
    (e.source == DemoSource::Scripted ? s.scripted : s.human) += 1;
    s.steps += e.steps();
    returns += e.episode_return();
    successes += e.success() ? 1 : 0;
    if (e.terminated)
      ++s.terminated;
    else if (e.truncated)
      ++s.truncated;
    else
      ++s.stopped;
    for (const StepInfo& info : e.infos) {
      if (info.collision) {
        ++s.collisions;
        break;
      }
    }
  }
  if (s.episodes > 0) {
    s.success_rate = static_cast<double>(successes) / s.episodes;
    s.mean_return = returns / s.episodes;
    s.mean_length = static_cast<double>(s.steps) / s.episodes;
  }
  return s;
}

}  // namespace rdsim
