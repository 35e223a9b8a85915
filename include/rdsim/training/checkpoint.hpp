#pragma once
#include <chrono>
#include <string>

#include <optional>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/training/evaluation.hpp"
#include "rdsim/vecenv/vec_env.hpp"

// The payload of checkpoint.bin (model_file.hpp holds the envelope): the algorithm's training
// state (weights first, so `rdsim replay checkpoint.bin` reads it like a model), the training
// loop's counters, then the envs (VecEnv::save: env states, observations, episode tracking).
namespace rdsim {

// Where a resumed run picks up the log files and the update count.
struct TrainerState {
  long long progress_rows = 0;
  long long episode_rows = 0;
  long long updates = 0;
  std::optional<EvalState> eval;  // a run with "eval" (rank 0's; the other ranks' are zero)
};

std::string checkpoint_payload(const Algorithm& algo, const VecEnv& vec, const TrainerState& state);

// Loads a payload into `algo` and `vec` (built from the checkpoint's embedded config). Every field
// is validated (counters in range, values finite, sizes against what is left of the payload);
// rdsim::Error naming `source` otherwise. `report`: print the note when the envs cannot resume
// exactly (false on MPI ranks other than 0, so the note appears once). `eval`: the run has "eval"
// (its checkpoints hold the evaluations' state after the counters; the config tells, so checkpoints
// of runs without it read as before).
TrainerState restore_checkpoint(const std::string& payload, Algorithm& algo, VecEnv& vec, const std::string& source,
                                bool report = true, bool eval = false);

// When the run's files are saved: checkpoint.bin and model.bin together, every
// checkpoint_interval env steps and every checkpoint_seconds of wall time (TrainConfig), so that a
// kill -9 loses at most about that much work. When writing a checkpoint takes long (a large
// replay buffer), the time period stretches to 20 times the write, so saving stays under 5%.
class CheckpointSchedule {
public:
  CheckpointSchedule(long long interval_steps, double interval_seconds, long long steps);
  bool due(long long steps) const;
  // Call around each save.
  void start() { started_ = Clock::now(); }
  void done(long long steps);

private:
  using Clock = std::chrono::steady_clock;
  long long interval_;
  double seconds_;
  long long next_step_ = 0;
  Clock::time_point last_, started_;
  double last_duration_ = 0.0;
};

// A resumed run keeps the first `rows` data rows of the log at `path`: rdsim::Error naming the
// checkpoint when the log has fewer (the folder's logs belong to another run, or were cut).
void check_log_rows(const std::string& path, long long rows, const std::string& checkpoint);

}  // namespace rdsim
