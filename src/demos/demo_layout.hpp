#pragma once
// Byte positions of the demonstration file layout documented in include/rdsim/demos/demo_file.hpp,
// shared by the reader (demo_file.cpp) and the writer (demo_writer.cpp).
#include <cstddef>
#include <cstdint>
#include <string>

namespace rdsim::demo_layout {

inline constexpr char magic[8] = {'R', 'D', 'S', 'I', 'M', 'D', 'E', 'M'};
inline constexpr std::uint32_t record_magic = 0x53495045u;  // the bytes "EPIS"
inline constexpr std::size_t commit_offset = 16;   // u64 committed length, u64 episodes, u64 checksum
inline constexpr std::size_t commit_size = 24;
inline constexpr std::size_t header_offset = 40;   // u64 header length, header JSON, u64 checksum

// The 24 bytes written at commit_offset: committed length, episodes, and the checksum of the file's
// first 32 bytes (magic, version, reserved, length, episodes).
std::string commit_record(std::uint64_t committed_length, std::uint64_t episodes);

}  // namespace rdsim::demo_layout
