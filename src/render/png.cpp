#include "rdsim/render/png.hpp"

#include <algorithm>
#include <limits>

#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace rdsim {
namespace {

void put_u32_be(std::string& out, std::uint32_t v) {
  out.push_back(static_cast<char>(v >> 24));
  out.push_back(static_cast<char>(v >> 16));
  out.push_back(static_cast<char>(v >> 8));
  out.push_back(static_cast<char>(v));
}

void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32_be(out, static_cast<std::uint32_t>(data.size()));
  const size_t type_at = out.size();
  out.append(type, 4);
  out += data;
  // The CRC covers the chunk type and data, not the length.
  put_u32_be(out, crc32(std::string_view(out).substr(type_at)));
}

// zlib stream (RFC 1950) around stored deflate blocks (RFC 1951, BTYPE 00).
std::string zlib_stored(const std::string& raw) {
  constexpr size_t kMaxStored = 65535;
  std::string z;
  z.reserve(raw.size() + raw.size() / kMaxStored * 5 + 16);
  z.push_back(static_cast<char>(0x78));  // deflate, 32 KiB window
  z.push_back(static_cast<char>(0x01));  // no dictionary, fastest; (0x78 << 8 | 0x01) % 31 == 0
  size_t at = 0;
  do {
    const size_t len = std::min(kMaxStored, raw.size() - at);
    const bool last = at + len == raw.size();
    z.push_back(static_cast<char>(last ? 1 : 0));  // BFINAL, BTYPE = 00 (stored)
    z.push_back(static_cast<char>(len & 0xFF));
    z.push_back(static_cast<char>(len >> 8));
    z.push_back(static_cast<char>(~len & 0xFF));
    z.push_back(static_cast<char>((~len >> 8) & 0xFF));
    z.append(raw, at, len);
    at += len;
  } while (at < raw.size());
  put_u32_be(z, adler32(raw));
  return z;
}

}  // namespace

std::string encode_png(int width, int height, int channels, const std::uint8_t* pixels) {
  if (width < 1 || height < 1)
    throw Error("png: image size must be positive, got " + std::to_string(width) + "x" +
                std::to_string(height));
  if (channels != 1 && channels != 3 && channels != 4)
    throw Error("png: channels must be 1, 3 or 4, got " + std::to_string(channels));
  const size_t row = static_cast<size_t>(width) * static_cast<size_t>(channels);
  if (row + 1 > std::numeric_limits<std::uint32_t>::max() / static_cast<size_t>(height))
    throw Error("png: image too large for one PNG");

  // Each scanline starts with its filter type; 0 (None) keeps the bytes as they are.
  std::string raw;
  raw.reserve((row + 1) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(pixels) + row * static_cast<size_t>(y), row);
  }

  std::string ihdr;
  put_u32_be(ihdr, static_cast<std::uint32_t>(width));
  put_u32_be(ihdr, static_cast<std::uint32_t>(height));
  const char colour_type = channels == 1 ? 0 : channels == 3 ? 2 : 6;
  ihdr += {8, colour_type, 0, 0, 0};  // bit depth, colour type, deflate, filter set 0, no interlace

  std::string png("\x89PNG\r\n\x1a\n", 8);
  put_chunk(png, "IHDR", ihdr);
  put_chunk(png, "IDAT", zlib_stored(raw));
  put_chunk(png, "IEND", "");
  return png;
}

void write_png(const std::string& path, int width, int height, int channels,
               const std::uint8_t* pixels) {
  std::string png;
  try {
    png = encode_png(width, height, channels, pixels);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  write_file_atomic(path, png);
}

}  // namespace rdsim
