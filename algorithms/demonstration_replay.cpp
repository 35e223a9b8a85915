#include "rdsim/algorithms/demonstration_replay.hpp"

#include "rdsim/core/assert.hpp"
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

std::vector<int> planar_position_rows(const Spec& spec) {
  std::vector<int> rows;
  const ObservationSpace& space = spec.observation;
  if (!spec.goal.active() || space.type != ObsType::Float32 || space.part("joint_positions").second > 0) return rows;
  int at = 0;
  for (const ObservationPart& p : space.parts) {
    const bool points = (p.size == 3 && p.name.ends_with("_position")) || p.name == "achieved_goal" ||
                        p.name == "desired_goal";
    if (points)
      for (int k = 0; k + 2 < p.size; k += 3) rows.push_back(at + k);
    at += p.size;
  }
  return rows;
}

DemonstrationReplay::DemonstrationReplay(const DemoFile& demos, const Spec& spec, const std::optional<HerConfig>& her,
                                         const std::function<Eigen::VectorXf(const Action&)>& normalize, double shift,
                                         double scatter, bool scatter_goal)
    : buffer_(count_steps(demos), spec.observation, spec.action.dim()), shift_(static_cast<float>(shift)), scatter_(scatter) {
  if (scatter_ > 0.0) scatter_by_.emplace(demos, spec, scatter_goal);
  if (shift_ > 0.0f) {
    shift_rows_ = planar_position_rows(spec);
    RDSIM_ASSERT(!shift_rows_.empty(), "demonstrations.shift is checked against the env before the buffer is built");
  }
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
  std::vector<long long> drawn(scatter_by_ ? static_cast<std::size_t>(count) : 0);  // the slots, for the scatter
  long long* slots = scatter_by_ ? drawn.data() : nullptr;
  if (her_)
    her_->sample_into(buffer_, first, count, rng, out, slots);
  else
    buffer_.sample_into(first, count, rng, out, slots);
  if (scatter_by_)
    for (int j = first; j < first + count; ++j)
      // A draw decides only for a share below 1, so that scatter 1 scatters every transition.
      if (scatter_ >= 1.0 || rng.uniform() < scatter_) scatter_by_->apply(slots[j - first], j, rng, out);
  if (shift_ > 0.0f) shift_into(first, count, rng, out);
}

void DemonstrationReplay::shift_into(int first, int count, Rng& rng, ReplayBatch& out) const {
  for (int j = first; j < first + count; ++j) {
    const auto dx = static_cast<float>(rng.uniform(-shift_, shift_));
    const auto dy = static_cast<float>(rng.uniform(-shift_, shift_));
    for (const int r : shift_rows_) {
      out.observations(r, j) += dx;
      out.observations(r + 1, j) += dy;
      out.next_observations(r, j) += dx;
      out.next_observations(r + 1, j) += dy;
    }
  }
}

}  // namespace rdsim
