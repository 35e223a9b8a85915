#pragma once
#include <cstdint>
#include <string_view>

namespace rdsim {

// CRC-32 (ISO-HDLC / zlib / PNG: reflected polynomial 0xEDB88320, init and final xor ~0).
// Pass the previous result as `crc` to continue over split data.
std::uint32_t crc32(std::string_view data, std::uint32_t crc = 0);

// CRC-32C (Castagnoli: reflected polynomial 0x82F63B78, init and final xor ~0), the checksum of
// TFRecord files (TensorBoard's event files); pass the previous result to continue.
std::uint32_t crc32c(std::string_view data, std::uint32_t crc = 0);

// Adler-32 as in RFC 1950 (zlib streams); pass the previous result to continue.
std::uint32_t adler32(std::string_view data, std::uint32_t adler = 1);

// FNV-1a 64 (offset basis 0xcbf29ce484222325, prime 0x100000001b3): the model and checkpoint
// files' checksum. It detects damage (truncation, flipped bits), not tampering.
std::uint64_t fnv1a64(std::string_view bytes);

}  // namespace rdsim
