#pragma once
#include <cstdint>
#include <string>
#include <string_view>

// TFRecord framing, the container of TensorBoard's event files: each record is
//   uint64 length (little-endian) | uint32 masked CRC-32C of those 8 bytes | data | uint32 masked CRC-32C of data
// (all little-endian). The mask keeps a CRC of data that holds CRCs from looking like one.
namespace rdsim {

// CRC-32C rotated right by 15 bits plus 0xa282ead8, as TFRecord stores it.
std::uint32_t masked_crc32c(std::string_view data);

// One record holding `data`, framed as above.
std::string tfrecord(std::string_view data);

}  // namespace rdsim
