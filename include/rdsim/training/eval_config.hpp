#pragma once
#include "rdsim/core/config_fields.hpp"

// The "eval" object of a training config: the policy judged every `every` env steps on `episodes`
// episodes of its own env, with deterministic actions (SB3's EvalCallback). The rows go to eval.csv,
// the best policy so far (by mean return) to best_model.bin (training/evaluation.hpp).
namespace rdsim {

struct EvalConfig {
  long long every = 10000;
  int episodes = 10;
};

template <class V, class C>
  requires config::Describes<C, EvalConfig>
void describe(V& v, C& c) {
  v.field("every", c.every, config::Range{1LL, 1'000'000'000'000LL},
          "env steps (all envs and ranks together) between evaluations: after the first update that reaches each "
          "multiple of it");
  v.field("episodes", c.episodes, config::Range{1, 100000},
          "episodes per evaluation, with the most likely actions, on an env of its own: the first reset with the "
          "run's seed, the rest continuing from it (what `rdsim replay MODEL --episodes N` runs)");
}

}  // namespace rdsim
