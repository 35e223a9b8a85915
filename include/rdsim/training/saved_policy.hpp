#pragma once
#include <memory>
#include <string>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/training/model_file.hpp"
#include "rdsim/training/train_config.hpp"

// A model.bin (or checkpoint.bin) loaded into its algorithm, without building its env: what Python's
// rdsim.load_model and `rdsim export` act with (`rdsim replay` also builds the env).
namespace rdsim {

struct SavedPolicy {
  TrainConfig config;  // the embedded config
  Spec spec;           // of the env the config builds
  std::unique_ptr<Algorithm> algorithm;
};

// rdsim::Error naming `path` for a damaged or foreign file, a config or spec that does not fit, or
// weights that do not fit the algorithm.
SavedPolicy load_saved_policy(const std::string& path);

}  // namespace rdsim
