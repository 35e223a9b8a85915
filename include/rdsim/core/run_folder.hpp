#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// What `rdsim train` leaves in a run folder, as the tools that only read runs (the dashboard,
// `rdsim plot`) see it: progress.csv, episodes.csv and config.json (src/app/train.cpp writes them).
namespace rdsim {

inline constexpr const char* progress_csv_name = "progress.csv";
inline constexpr const char* episodes_csv_name = "episodes.csv";
inline constexpr const char* run_config_name = "config.json";

// A run's identity from its config.json. Reading is lenient: a run whose config.json is missing or
// unreadable (a run that is just starting, a foreign folder) has empty fields, never an error.
struct RunInfo {
  std::string dir;                    // the run folder
  std::string env;                    // config.json env.name
  std::string algorithm;              // config.json algorithm ("ppo")
  std::optional<std::uint64_t> seed;  // config.json seed
};
RunInfo read_run_info(const std::string& dir);

// The run folders (folders holding a progress.csv, or a config.json: a run that has not finished its
// first update yet) at or below `root`, at most max_depth levels
// down and at most max_runs of them, sorted by path. Symbolic links to folders are not followed
// and unreadable folders are passed over. Throws rdsim::Error when `root` is not a folder.
std::vector<std::string> find_run_folders(const std::string& root, int max_depth = 4, std::size_t max_runs = 1000);

}  // namespace rdsim
