#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// `rdsim train`: trains the algorithm of a config on its env (src/app/train.cpp). Bad input
// is reported by throwing rdsim::Error; returns the process exit code.
namespace rdsim {

class Communicator;  // rdsim/parallel/communicator.hpp

struct TrainOptions {
  std::string config_path;
  std::string resume_dir;                   // continue from this run folder's last checkpoint
  std::optional<std::uint64_t> seed;        // overrides the config's seed
  std::optional<long long> timesteps;       // overrides the config's total_timesteps
  std::string log_dir;                      // overrides the config's log_dir
  bool quiet = false;                       // no progress line
  std::optional<int> threads;               // overrides the config's num_threads
  Communicator* communicator = nullptr;     // the MPI job this process is a rank of; null: one process
};
int train_command(const TrainOptions& options);

}  // namespace rdsim
