#include "rdsim/tensorboard/event_proto.hpp"

#include <cstring>

namespace rdsim {
namespace {

// Protocol buffer wire types.
constexpr unsigned kVarint = 0, kFixed64 = 1, kBytes = 2, kFixed32 = 5;

void varint(std::string& out, std::uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

void key(std::string& out, unsigned field, unsigned wire_type) { varint(out, (field << 3) | wire_type); }

template <typename Float, typename Bits>
void fixed(std::string& out, unsigned field, unsigned wire_type, Float value) {
  key(out, field, wire_type);
  Bits bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (std::size_t i = 0; i < sizeof bits; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xFFu));
}

void bytes(std::string& out, unsigned field, const std::string& value) {
  key(out, field, kBytes);
  varint(out, value.size());
  out += value;
}

// wall_time (1) and step (2): every event starts with them. A negative step is its 64-bit
// two's complement, as protobuf encodes int64.
std::string event_head(double wall_time, long long step) {
  std::string e;
  fixed<double, std::uint64_t>(e, 1, kFixed64, wall_time);
  key(e, 2, kVarint);
  varint(e, static_cast<std::uint64_t>(step));
  return e;
}

}  // namespace

std::string encode_file_version_event(double wall_time) {
  std::string e = event_head(wall_time, 0);
  bytes(e, 3, "brain.Event:2");
  return e;
}

std::string encode_scalars_event(double wall_time, long long step, const std::vector<Scalar>& scalars) {
  std::string summary;
  for (const auto& [tag, value] : scalars) {
    std::string v;
    bytes(v, 1, tag);
    fixed<float, std::uint32_t>(v, 2, kFixed32, static_cast<float>(value));
    bytes(summary, 1, v);
  }
  std::string e = event_head(wall_time, step);
  bytes(e, 5, summary);
  return e;
}

std::string encode_session_start_event(double wall_time, long long step) {
  std::string session_log;
  key(session_log, 1, kVarint);
  varint(session_log, 1);  // SessionStatus START
  std::string e = event_head(wall_time, step);
  bytes(e, 7, session_log);
  return e;
}

}  // namespace rdsim
