#pragma once
#include <optional>
#include <string>

#include "rdsim/training/setting_names.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/memory_estimate.hpp"

// The memory a training run may use, checked before anything large is allocated (src/training/
// memory_check.cpp). The limit: `train --max-memory GB` when given, else 80% of the machine's
// physical memory, lowered to 80% of what the address-space limit (ulimit -v) leaves.
namespace rdsim {

struct MemoryLimit {
  double bytes = 0.0;
  std::string why;  // "80% of this machine's 16.8 GB", "--max-memory 4"
  SettingNames names;  // how the message names the setting that raises the limit
};
MemoryLimit memory_limit(std::optional<double> max_memory_gb, const SettingNames& names = {});

// What a run of `config` with envs of `spec` will allocate: envs (envs/registry) and learner
// (algorithms/algorithm_config).
MemoryEstimate estimate_training_memory(const TrainConfig& config, const Spec& spec);

// rdsim::Error naming `where` (the config) with the estimate's largest items when it is over the limit.
void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, const std::string& where);

}  // namespace rdsim
