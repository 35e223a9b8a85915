#pragma once
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"
#include "rdsim/core/run_files.hpp"

// The runs a dashboard serves: every run folder under its roots (find_run_folders), each named by
// an id made from its root's number and its path below that root ("0:jaka_button/seed1"). A
// request names a run only by such an id, and the index answers with a path it found by scanning
// the roots itself, so no request can make it open a file outside them; a progress.csv reached
// through a symbolic link that leaves its root is refused as well.
namespace rdsim {

struct IndexedRun {
  std::string id;             // "0:jaka_button/seed1"
  std::string label;          // "jaka_button/seed1": the path below the root (see rescan)
  RunInfo info;               // env, algorithm, seed from config.json
  std::string progress_path;  // <run folder>/progress.csv
  std::size_t root = 0;       // which root it was found under
  std::string below;          // the run folder's path below its root ("." for the root itself)
};

// A run file reached through a link that leads out of its root.
struct RunOutsideRoot : Error {
  using Error::Error;
};

class RunIndex {
public:
  // Throws rdsim::Error when a root is not a folder.
  explicit RunIndex(std::vector<std::string> roots);

  // Every run found, rescanning the roots when the last scan is older than a second.
  std::vector<IndexedRun> runs();
  // The run with this id (rescans only when it is not known, at most five times a second), or nothing.
  std::optional<IndexedRun> find(const std::string& id);
  // Whether `file` (after resolving links) lies inside the folder of root `root_number`.
  bool inside_root(const std::string& file, std::size_t root_number) const;
  // The run's log `name` (progress.csv, eval.csv), opened below its root in one step
  // (InputFile::beneath); nothing when the run has not written it yet. RunOutsideRoot when a link
  // leads out of the root on the way, rdsim::Error when it is not a regular file.
  std::optional<InputFile> open_log(const IndexedRun& run, const char* name) const;

private:
  void rescan(bool force);

  std::vector<std::string> roots_, canonical_roots_;
  std::mutex mutex_;
  std::vector<IndexedRun> runs_;
  std::chrono::steady_clock::time_point scanned_{};
  bool scanned_once_ = false;
};

}  // namespace rdsim
