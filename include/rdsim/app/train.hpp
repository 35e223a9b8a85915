#pragma once
#include "rdsim/training/trainer.hpp"

// `rdsim train`: runs a Trainer (rdsim/training/trainer.hpp) with SIGINT/SIGTERM handled. Bad input
// is reported by throwing rdsim::Error; returns the process exit code (0, or 130/143 when a
// SIGINT/SIGTERM stopped the run after saving it: training/interrupt.hpp).
namespace rdsim {

int train_command(TrainerSettings settings);

}  // namespace rdsim
