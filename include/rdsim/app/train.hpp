#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/app/train_config.hpp"

// `rdsim train`: trains the algorithm of a config on its env (src/app/train.cpp). Bad input
// is reported by throwing rdsim::Error; returns the process exit code (0, or 130/143 when a
// SIGINT/SIGTERM stopped the run after saving it: app/interrupt.hpp).
namespace rdsim {

class Communicator;  // rdsim/parallel/communicator.hpp

struct TrainOptions {
  std::string config_path;
  std::string resume_dir;                   // continue from this run folder's last checkpoint
  // Run settings given on the command line (--seed, --timesteps, --log-dir), read with the
  // config file's rules (train_config.hpp).
  std::vector<ConfigOverride> overrides;
  bool overwrite = false;                   // a new run may replace another run's files in its folder
  std::optional<double> max_memory_gb;      // the memory limit (app/memory_check.hpp)
  bool quiet = false;                       // no progress line
  std::optional<int> threads;               // overrides the config's num_threads
  Communicator* communicator = nullptr;     // the MPI job this process is a rank of; null: one process
  std::string dashboard;                    // serve the live dashboard at HOST:PORT while training
};
int train_command(const TrainOptions& options);

}  // namespace rdsim
