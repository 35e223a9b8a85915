#pragma once
#include <cstdint>
#include <string>

namespace rdsim {

// A complete PNG file for an 8-bit image of `channels` 1 (grey), 3 (RGB) or 4 (RGBA), rows
// top to bottom, tightly packed. The zlib stream uses stored (uncompressed) deflate blocks:
// fast, deterministic and simple; files are about width * height * channels bytes.
// rdsim::Error for a size below 1 or other channel counts.
std::string encode_png(int width, int height, int channels, const std::uint8_t* pixels);

// encode_png written atomically (rdsim::write_file_atomic); rdsim::Error naming `path`.
void write_png(const std::string& path, int width, int height, int channels,
               const std::uint8_t* pixels);

}  // namespace rdsim
