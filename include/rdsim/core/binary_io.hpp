#pragma once
#include <cstdint>
#include <iosfwd>
#include <string>

// rdsim's one home for binary I/O: little-endian fixed-size values and length-prefixed byte
// strings, the building blocks of model, checkpoint, network-parameter and env-state formats.
// Readers throw rdsim::Error naming `source` (the file or message) when the stream ends early,
// so a truncated file is a clear error, never garbage. Little-endian hosts only (the build
// rejects big-endian targets).
namespace rdsim {

void write_u32(std::ostream& out, std::uint32_t v);
void write_u64(std::ostream& out, std::uint64_t v);
void write_f32(std::ostream& out, float v);
void write_f64(std::ostream& out, double v);
// u64 length, then the bytes.
void write_string(std::ostream& out, const std::string& s);

std::uint32_t read_u32(std::istream& in, const std::string& source);
std::uint64_t read_u64(std::istream& in, const std::string& source);
float read_f32(std::istream& in, const std::string& source);
double read_f64(std::istream& in, const std::string& source);
// A damaged length never makes it allocate more than the rest of the stream holds.
std::string read_string(std::istream& in, const std::string& source);
// A u64 count of items of `item_bytes` bytes each, checked to fit in what is left of the stream,
// so a damaged count can never make a reader allocate more than the file holds.
std::uint64_t read_count(std::istream& in, std::uint64_t item_bytes, const std::string& source);
// Bytes from the current position to the end of the stream.
std::uint64_t bytes_left(std::istream& in);
// Exactly n bytes into `data`.
void read_bytes(std::istream& in, void* data, std::size_t n, const std::string& source);

}  // namespace rdsim
