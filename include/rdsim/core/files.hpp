#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace rdsim {

// Writes `data` to a uniquely named temporary file beside `path` (mkstemp: ".NAME.XXXXXX.tmp"),
// fsyncs it, renames it over `path` and fsyncs the folder, so a reader (or a crash, or a second
// writer) never sees a half-written model or log: the old file or the new one. Throws
// rdsim::Error on failure and removes the temporary.
void write_file_atomic(const std::string& path, std::string_view data);

// Whether `name` is a temporary file write_file_atomic leaves behind when killed mid-write.
bool is_atomic_write_leftover(const std::string& name);

// Whole file as bytes, at most `max_bytes`, the limit for its kind of file: only a regular file is
// read, and a larger one is an rdsim::Error naming it and the limit before anything that size is
// allocated (input_file.hpp: a FIFO, device or socket is refused without blocking). rdsim::Error
// naming the file when it cannot be read. rdsim's readers pass their kind's limit; the default
// (none) is for tests and tools.
std::string read_file(const std::string& path, std::uint64_t max_bytes = UINT64_MAX);

}  // namespace rdsim
