#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

// One protocol message as it travels: a JSON header (ZeroMQ frame 0) and raw little-endian arrays
// (frames 1..n), each described in the header's "arrays" list, in frame order:
//   {"arrays": [{"name": "observation", "dtype": "float32", "shape": [6]}], ...}
// so images and observations are never JSON-encoded (docs/protocol.md).
namespace rdsim::remote {

enum class DType { Float32, UInt8 };

struct ArrayFrame {
  std::string name;
  DType dtype = DType::Float32;
  std::vector<int> shape;
  std::string bytes;  // product(shape) x element size

  static ArrayFrame float32(std::string name, const float* data, std::vector<int> shape);
  static ArrayFrame uint8(std::string name, const std::uint8_t* data, std::vector<int> shape);
  std::size_t count() const;
  // The elements as floats (Float32 only; rdsim::Error otherwise).
  std::vector<float> floats() const;
};

struct Message {
  nlohmann::json header = nlohmann::json::object();
  std::vector<ArrayFrame> arrays;

  // The array called `name`, or nullptr.
  const ArrayFrame* find(std::string_view name) const;
};

const char* to_string(DType dtype);
std::size_t element_size(DType dtype);

// The frames of `m`: the header (with "arrays" filled in from m.arrays) then each array's bytes.
std::vector<std::string> encode_message(const Message& m);
// Frame 0 of `m` alone (the header text with its "arrays" list): senders follow it with the
// arrays' bytes straight from m.arrays, without copying them into frames first.
std::string encode_header(const Message& m);

// Reads frames back into a Message, checking everything a hostile peer could get wrong: the
// number of frames, a header of at most `max_header_bytes` that is a JSON object nested at most
// max_json_depth deep, and "arrays" entries (name, known dtype, shape of at most 4 dims) whose
// sizes match their frames exactly, each at most `max_frame_bytes`. rdsim::Error with a message
// for the peer otherwise. The "arrays" key is removed from the returned header.
Message decode_message(const std::vector<std::string_view>& frames, std::size_t max_header_bytes,
                       std::size_t max_frame_bytes);

// The deepest nesting of JSON objects/arrays in `text` (strings skipped), counted without parsing,
// so an attacker's [[[[...]]]] is refused before a parser sees it.
int json_depth(std::string_view text);

}  // namespace rdsim::remote
