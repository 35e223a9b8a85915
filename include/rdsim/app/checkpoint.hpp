#pragma once
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/algorithms/vec_env.hpp"

// The payload of checkpoint.bin (model_file.hpp holds the envelope): the algorithm's training
// state (weights first, so `rdsim replay checkpoint.bin` reads it like a model), the training
// loop's counters, then the envs (VecEnv::save: env states, observations, episode tracking).
namespace rdsim {

// Where a resumed run picks up the log files and the update count.
struct TrainerState {
  long long progress_rows = 0;
  long long episode_rows = 0;
  long long updates = 0;
};

std::string checkpoint_payload(const Algorithm& algo, const VecEnv& vec, const TrainerState& state);

// Loads a payload into `algo` and `vec` (built from the checkpoint's embedded config). Every field
// is validated (counters in range, values finite, sizes against what is left of the payload);
// rdsim::Error naming `source` otherwise.
TrainerState restore_checkpoint(const std::string& payload, Algorithm& algo, VecEnv& vec, const std::string& source);

// A resumed run keeps the first `rows` data rows of the log at `path`: rdsim::Error naming the
// checkpoint when the log has fewer (the folder's logs belong to another run, or were cut).
void check_log_rows(const std::string& path, long long rows, const std::string& checkpoint);

}  // namespace rdsim
