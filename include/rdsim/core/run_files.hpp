#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// The files `rdsim train` leaves in a run folder (src/app/train.cpp writes them), named once here
// for every library that writes or reads runs, and what the tools that only read runs (the
// dashboard, `rdsim plot`) learn from them.
namespace rdsim {

inline constexpr const char* run_config_name = "config.json";    // the resolved config
inline constexpr const char* progress_csv_name = "progress.csv";  // one row per update
inline constexpr const char* episodes_csv_name = "episodes.csv";  // one row per finished episode
inline constexpr const char* model_file_name = "model.bin";       // the policy (training/model_file.hpp)
inline constexpr const char* checkpoint_file_name = "checkpoint.bin";  // the model plus what --resume needs
inline constexpr const char* pretrain_csv_name = "pretrain.csv";  // one row per epoch of learning from demonstrations
inline constexpr const char* eval_csv_name = "eval.csv";          // one row per evaluation ("eval")
inline constexpr const char* best_model_file_name = "best_model.bin";  // the best evaluation's policy

// All of them.
inline constexpr std::array<const char*, 8> run_file_names = {run_config_name,      progress_csv_name,    episodes_csv_name,
                                                              model_file_name,      checkpoint_file_name, pretrain_csv_name,
                                                              eval_csv_name,        best_model_file_name};

// A run's identity from its config.json. Reading is lenient: a run whose config.json is missing or
// unreadable (a run that is just starting, a foreign folder) has empty fields, never an error.
struct RunInfo {
  std::string dir;                    // the run folder
  std::string env;                    // config.json env.name
  std::string algorithm;              // config.json algorithm ("ppo")
  std::optional<std::uint64_t> seed;  // config.json seed
};
RunInfo read_run_info(const std::string& dir);
// The same for the run folder `below` under `root`, its config.json opened without following a
// link out of `root` (InputFile::beneath): what a server of the runs under a folder reads.
RunInfo read_run_info_beneath(const std::string& root, const std::string& below);

// The run folders (folders holding a progress.csv, or a config.json: a run that has not finished its
// first update yet) at or below `root`, at most max_depth levels
// down and at most max_runs of them, sorted by path. Symbolic links to folders are not followed
// and unreadable folders are passed over. Throws rdsim::Error when `root` is not a folder.
std::vector<std::string> find_run_folders(const std::string& root, int max_depth = 4, std::size_t max_runs = 1000);

}  // namespace rdsim
