#pragma once
#include <filesystem>
#include <memory>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {

// The file of the config's "demonstrations", read (errors name the config and its key).
DemoFile read_demonstrations(const TrainConfig& config);

// The demonstrations whose states start training episodes (start_fraction): `demos` (the
// config's file, read by read_demonstrations), or demonstrations.start_file read when the config
// names one (errors name that key).
std::shared_ptr<const DemoFile> starting_demonstrations(const TrainConfig& config, std::shared_ptr<const DemoFile> demos);

// The demonstrations checked against the env, then handed to the algorithm (pre-training on a
// fresh run; `dir`/pretrain.csv gets one row per epoch; `dir` is empty on MPI ranks other than 0,
// which write nothing).
void learn_from_demonstrations(const TrainConfig& config, const DemoFile& demos, Algorithm& algo, const Spec& spec,
                               bool resume, const std::filesystem::path& dir, bool quiet);

}  // namespace rdsim
