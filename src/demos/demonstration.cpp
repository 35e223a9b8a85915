#include "rdsim/demos/demonstration.hpp"

namespace rdsim {

const char* to_string(DemoSource source) { return source == DemoSource::Scripted ? "scripted" : "human"; }

void DemoEpisode::start(Observation first) {
  observations.clear();
  actions.clear();
  rewards.clear();
  infos.clear();
  terminated = truncated = false;
  observations.push_back(std::move(first));
}

void DemoEpisode::add(const Action& action, const StepResult& result) {
  actions.push_back(action);
  observations.push_back(result.observation);
  rewards.push_back(result.reward);
  infos.push_back(result.info);
  terminated = result.terminated;
  truncated = result.truncated;
}

double DemoEpisode::episode_return() const {
  double sum = 0.0;
  for (float r : rewards) sum += r;
  return sum;
}

bool DemoEpisode::success() const {
  for (const StepInfo& info : infos)
    if (info.success) return true;
  return false;
}

}  // namespace rdsim
