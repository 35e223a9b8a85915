#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace rdsim {

// Creates the folders above `path` that do not exist yet (`demos/x.demo` on a clean clone: every
// output file rdsim writes gets its folder, as `train --log-dir` does). rdsim::Error naming `path`
// and the folder when one cannot be made (a file in the way, no permission).
void create_parent_folders(const std::string& path);

// Creates the parent folders (create_parent_folders), then
// writes `data` to a uniquely named temporary file beside `path` (mkstemp: ".NAME.XXXXXX.tmp"),
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

// read_file, for a file another rdsim command makes: when it does not exist, the error says how to
// make it ("keys/server.key: cannot open: No such file or directory; make it with: rdsim keygen ...").
std::string read_file_or_hint(const std::string& path, const std::string& how_to_make_it,
                              std::uint64_t max_bytes = UINT64_MAX);
// The same error when `path` does not exist, for readers that open the file themselves (InputFile).
void require_file_or_hint(const std::string& path, const std::string& how_to_make_it);

}  // namespace rdsim
