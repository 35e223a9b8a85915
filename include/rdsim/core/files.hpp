#pragma once
#include <string>
#include <string_view>

namespace rdsim {

// Writes `data` to a temporary file beside `path`, flushes it and renames it over `path`,
// so a reader never sees a half-written model or log. Throws rdsim::Error on failure.
void write_file_atomic(const std::string& path, std::string_view data);

// Whole file as bytes; rdsim::Error naming the file when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace rdsim
