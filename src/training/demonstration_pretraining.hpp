#pragma once
#include <filesystem>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {

// The config's "demonstrations": the file read and checked against the env, then handed to the
// algorithm (pre-training on a fresh run; `dir`/pretrain.csv gets one row per epoch; `dir` is
// empty on MPI ranks other than 0, which write nothing).
void learn_from_demonstrations(const TrainConfig& config, Algorithm& algo, const Spec& spec, bool resume,
                               const std::filesystem::path& dir, bool quiet);

}  // namespace rdsim
