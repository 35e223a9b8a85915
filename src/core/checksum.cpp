#include "rdsim/core/checksum.hpp"

#include <algorithm>
#include <array>

namespace rdsim {
namespace {

// Byte-at-a-time table of a reflected CRC-32 with this polynomial.
constexpr std::array<std::uint32_t, 256> make_crc_table(std::uint32_t polynomial) {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? polynomial ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  return table;
}

constexpr auto kCrcTable = make_crc_table(0xEDB88320u);
constexpr auto kCrc32cTable = make_crc_table(0x82F63B78u);

std::uint32_t reflected_crc(const std::array<std::uint32_t, 256>& table, std::string_view data, std::uint32_t crc) {
  std::uint32_t c = ~crc;
  for (unsigned char byte : data) c = table[(c ^ byte) & 0xFFu] ^ (c >> 8);
  return ~c;
}

}  // namespace

std::uint32_t crc32(std::string_view data, std::uint32_t crc) { return reflected_crc(kCrcTable, data, crc); }

std::uint32_t crc32c(std::string_view data, std::uint32_t crc) { return reflected_crc(kCrc32cTable, data, crc); }

std::uint32_t adler32(std::string_view data, std::uint32_t adler) {
  constexpr std::uint32_t kMod = 65521;
  // 5552 bytes is the most that can be summed before the 32-bit sums may overflow.
  constexpr size_t kBlock = 5552;
  std::uint32_t a = adler & 0xFFFFu, b = adler >> 16;
  size_t i = 0;
  while (i < data.size()) {
    const size_t end = std::min(data.size(), i + kBlock);
    for (; i < end; ++i) {
      a += static_cast<unsigned char>(data[i]);
      b += a;
    }
    a %= kMod;
    b %= kMod;
  }
  return (b << 16) | a;
}

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace rdsim
