#pragma once
#include <bit>
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>

#include "rdsim/error.hpp"
#include "rdsim/nn/serialize.hpp"

// Doubles and byte strings in the nn:: stream format (little-endian u64 building blocks), for
// the training state that checkpoints carry besides tensors.
namespace rdsim {

inline void write_f64(std::ostream& out, double v) { nn::write_u64(out, std::bit_cast<std::uint64_t>(v)); }
inline double read_f64(std::istream& in, const std::string& source) {
  return std::bit_cast<double>(nn::read_u64(in, source));
}

inline void write_string(std::ostream& out, const std::string& s) {
  nn::write_u64(out, s.size());
  out.write(s.data(), static_cast<std::streamsize>(s.size()));
}
inline std::string read_string(std::istream& in, const std::string& source) {
  const std::uint64_t n = nn::read_u64(in, source);
  // A damaged length must not make us allocate gigabytes before noticing the stream is short.
  const auto pos = in.tellg();
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(pos);
  if (pos < 0 || end < 0 || n > static_cast<std::uint64_t>(end - pos)) throw Error(source + ": file is truncated");
  std::string s(n, '\0');
  in.read(s.data(), static_cast<std::streamsize>(n));
  if (!in) throw Error(source + ": file is truncated");
  return s;
}

}  // namespace rdsim
