#pragma once
#include <limits>
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/training/eval_config.hpp"

// A training run's periodic evaluation (the config's "eval" object): after the first update that
// reaches each multiple of `every` env steps, `episodes` episodes with the most likely actions on an
// env of its own (policy_episodes.hpp: the run's seed first, so `rdsim replay best_model.bin
// --episodes K` runs the same episodes), one row in eval.csv, and the trainer saves best_model.bin
// when the mean return beats every earlier evaluation's. The schedule depends on the step count
// alone and the evaluation env never touches the training envs or the algorithm's streams, so a run
// with evaluation trains exactly as one without, and a resumed run evaluates where an uninterrupted
// one does. Rank 0 of an MPI job evaluates (the ranks' weights are the same).
namespace rdsim {

// What a checkpoint keeps of the evaluations (checkpoint.hpp).
struct EvalState {
  long long rows = 0;  // of eval.csv
  double best_mean_return = -std::numeric_limits<double>::infinity();
};

struct EvalResult {
  long long timesteps = 0;
  int episodes = 0;
  double mean_return = 0.0, std_return = 0.0, min_return = 0.0, max_return = 0.0;
  double mean_length = 0.0, success_rate = 0.0;
  bool new_best = false;  // the best mean return so far: best_model.bin is due
  double seconds = 0.0;   // the evaluation's wall time
};

class Evaluation {
public:
  // `env`: the evaluation env (the run's env config, one env). `csv_path`: eval.csv, kept to the
  // checkpoint's rows when `resume`. `steps`: where the run stands.
  Evaluation(const EvalConfig& config, std::unique_ptr<Env> env, std::uint64_t seed, const std::string& csv_path,
             long long steps, const EvalState& state, bool resume);

  bool due(long long steps) const { return steps >= next_; }
  // Runs the episodes now, writes the eval.csv row and schedules the next evaluation.
  EvalResult run(long long steps, Algorithm& algo);
  EvalState state() const { return {csv_.rows(), best_}; }

  // "eval at 10240 steps: mean return -3.21 (sd 0.52), success 0.90, 10 episodes; new best".
  static std::string describe(const EvalResult& r);
  // eval.csv's columns.
  static const std::vector<std::string>& columns();

private:
  void schedule_after(long long steps) { next_ = (steps / every_ + 1) * every_; }

  long long every_;
  int episodes_;
  std::unique_ptr<Env> env_;
  std::uint64_t seed_;
  CsvWriter csv_;
  double best_;
  long long next_ = 0;
};

}  // namespace rdsim
