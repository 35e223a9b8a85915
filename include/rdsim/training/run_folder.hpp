#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "rdsim/training/setting_names.hpp"

// One training run per folder. A RunFolder holds an exclusive lock (flock on DIR/.rdsim.lock,
// which records the holder's pid) for the run's lifetime, so a second run on the same folder
// fails at once with the holder named, instead of both writing the same files. The kernel drops
// the lock when the process ends, however it ends.
namespace rdsim {

class RunFolder {
public:
  // New: the folder must not hold another run's files (run_files()); Resume: continue the run in
  // it; Overwrite: remove the old run's files first. Creates the folder when missing and removes
  // temporaries a killed writer left (files.hpp). rdsim::Error naming the folder otherwise, and
  // the settings that would help as `names` spells them.
  enum class Mode { New, Resume, Overwrite };
  RunFolder(const std::string& dir, Mode mode, const SettingNames& names = {});
  ~RunFolder();
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;

  const std::filesystem::path& path() const { return dir_; }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  // The files a run writes (named in core/run_files.hpp): config.json, progress.csv, episodes.csv,
  // model.bin, checkpoint.bin, pretrain.csv (a run with demonstrations).
  static const std::vector<std::string>& run_files();

private:
  std::filesystem::path dir_;
  int lock_fd_ = -1;
};

}  // namespace rdsim
