#pragma once

#include <string>

namespace rdsim {

// Where rdsim's assets/ and configs/ lie: $RDSIM_ROOT when set, else the source tree known at build
// time, else (that tree gone) the data an installed binary carries beside it: the Python package's
// rdsim/bin/rdsim reads rdsim/data (the package's import sets $RDSIM_ROOT by the same rule).
std::string repo_root();

// A file the user named (a config): the path as given when it exists or is absolute, else the same
// relative path under repo_root() when that exists, so `--config configs/jaka_button.json` finds the
// configs an installed rdsim carries from any folder; else the path as given (its error names it).
std::string shipped_file(const std::string& path);

}  // namespace rdsim
