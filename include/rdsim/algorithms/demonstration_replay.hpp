#pragma once
#include <functional>
#include <optional>

#include "rdsim/algorithms/her.hpp"
#include "rdsim/algorithms/hindsight_replay.hpp"
#include "rdsim/algorithms/replay_buffer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/rng.hpp"

// Demonstrated transitions for the off-policy methods (SAC, TD3/DDPG; Vecerik et al. 2017,
// Nair et al. 2018 "Overcoming exploration with demonstrations"): every demonstrated step in a
// buffer of its own that is never overwritten, from which each minibatch draws a fixed share, with
// hindsight goals too when the run uses HER (each demonstrated episode is one stream of its own).
namespace rdsim {

struct DemoFile;  // demos/demo_file.hpp

class DemonstrationReplay {
public:
  // Box actions are stored as the algorithm acts: `normalize` maps an env action to the
  // networks' [-1, 1]. Throws rdsim::Error naming the file when it holds no step.
  DemonstrationReplay(const DemoFile& demos, const Spec& spec, const std::optional<HerConfig>& her,
                      const std::function<Eigen::VectorXf(const Action&)>& normalize);

  long long transitions() const { return buffer_.size(); }
  const ReplayBuffer& buffer() const { return buffer_; }

  // `count` transitions into columns [first, first + count) of `out` (shaped by the caller).
  void sample_into(int first, int count, Rng& rng, ReplayBatch& out) const;

private:
  ReplayBuffer buffer_;
  std::optional<HindsightReplay> her_;
};

}  // namespace rdsim
