#pragma once
#include <memory>
#include <string>

#include "rdsim/training/model_file.hpp"
#include "rdsim/training/run_folder.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/training/trainer.hpp"

// The run's config and folder. A new run reads its config (file or JSON, with the settings'
// overrides) and takes a folder that holds no other run; a resumed one takes its folder first,
// then reads the config its checkpoint embeds. Either way the memory the config implies is
// checked before anything large exists. Under MPI rank 0 alone reads the files and holds the
// folder (and its lock); the other ranks get the config and the checkpoint from it.
namespace rdsim {

class Communicator;

struct RunStart {
  TrainConfig config;
  std::unique_ptr<RunFolder> folder;  // rank 0
  ModelFile checkpoint;               // resume only
  std::string checkpoint_path;        // resume only
};

RunStart start_run(const TrainerSettings& settings, Communicator& comm);

}  // namespace rdsim
