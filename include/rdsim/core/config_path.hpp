#pragma once
#include <string>

// The one rule for paths in configs: a path written in a config file is relative to that file's
// folder, a path given on a command line (or in code) to the current folder; either way the run
// records it absolute (config.json, model.bin), so `--resume` and `replay` find it from anywhere.
namespace rdsim {

// `path` taken relative to `folder` (empty: the current folder) as an absolute, normalised path;
// an empty or absolute `path` is returned as it is (normalised).
std::string path_from(const std::string& folder, const std::string& path);

}  // namespace rdsim
