#pragma once
#include <string>

// How the caller spells the run settings in messages: `rdsim train`'s flags, or the keyword
// arguments of the Python package's rdsim.train (a Python user passes resume=, not --resume).
namespace rdsim {

enum class Setting { Resume, Overwrite, LogDir, Seed, Timesteps, MaxMemory };

struct SettingNames {
  bool python = false;  // rdsim.train's keyword arguments instead of the command's flags

  // "--resume" / "resume=", "--overwrite" / "overwrite=True", ...
  std::string flag(Setting s) const;
  // The setting with a value: "--resume runs/x" / "resume=\"runs/x\"", "--max-memory 4" / "max_memory=4".
  std::string with(Setting s, const std::string& value) const;
  // The whole call that continues the run in `dir` (`more`: further settings, with()'s form):
  // "rdsim train --resume runs/x --timesteps N" / "rdsim.train(resume=\"runs/x\", timesteps=N)".
  std::string resume_call(const std::string& dir, const std::string& more = "") const;
};

}  // namespace rdsim
