#include "rdsim/algorithms/demonstration_replay.hpp"

#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_file.hpp"

namespace rdsim {
namespace {

long long count_steps(const DemoFile& demos) {
  long long steps = 0;
  for (const DemoEpisode& e : demos.episodes) steps += e.steps();
  if (steps == 0) throw Error(demos.path + ": holds no demonstrated step to learn from");
  return steps;
}

}  // namespace

DemonstrationReplay::DemonstrationReplay(const DemoFile& demos, const Spec& spec, const std::optional<HerConfig>& her,
                                         const std::function<Eigen::VectorXf(const Action&)>& normalize)
    : buffer_(count_steps(demos), spec.observation, spec.action.dim()) {
  if (her) her_.emplace(*her, spec.goal, buffer_.capacity());
  for (const DemoEpisode& e : demos.episodes) {
    for (int t = 0; t < e.steps(); ++t) {
      const auto i = static_cast<std::size_t>(t);
      const bool last = t == e.steps() - 1;
      // The last step of an episode the env did not end (truncated, or stopped by a person) bootstraps.
      buffer_.add(e.observations[i], normalize(e.actions[i]), e.rewards[i], e.observations[i + 1], e.terminated && last);
      // One stream: the episodes lie one after the other.
      if (her_) her_->added(buffer_.last_slot(), 0, 1, last);
    }
  }
}

void DemonstrationReplay::sample_into(int first, int count, Rng& rng, ReplayBatch& out) const {
  if (her_) {
    her_->sample_into(buffer_, first, count, rng, out);
    return;
  }
  buffer_.sample_into(first, count, rng, out);
}

}  // namespace rdsim
