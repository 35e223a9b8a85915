#include "rdsim/core/binary_io.hpp"

#include <bit>
#include <istream>
#include <ostream>

#include "rdsim/core/error.hpp"

static_assert(std::endian::native == std::endian::little,
              "rdsim's binary formats are written for little-endian hosts");

namespace rdsim {

void write_u32(std::ostream& out, std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); }
void write_u64(std::ostream& out, std::uint64_t v) { out.write(reinterpret_cast<const char*>(&v), 8); }
void write_f32(std::ostream& out, float v) { out.write(reinterpret_cast<const char*>(&v), 4); }
void write_f64(std::ostream& out, double v) { write_u64(out, std::bit_cast<std::uint64_t>(v)); }

void write_string(std::ostream& out, const std::string& s) {
  write_u64(out, s.size());
  out.write(s.data(), static_cast<std::streamsize>(s.size()));
}

void read_bytes(std::istream& in, void* data, std::size_t n, const std::string& source) {
  in.read(static_cast<char*>(data), static_cast<std::streamsize>(n));
  if (static_cast<std::size_t>(in.gcount()) != n) throw Error(source + ": file is truncated");
}

std::uint32_t read_u32(std::istream& in, const std::string& source) {
  std::uint32_t v;
  read_bytes(in, &v, 4, source);
  return v;
}

std::uint64_t read_u64(std::istream& in, const std::string& source) {
  std::uint64_t v;
  read_bytes(in, &v, 8, source);
  return v;
}

float read_f32(std::istream& in, const std::string& source) {
  float v;
  read_bytes(in, &v, 4, source);
  return v;
}

double read_f64(std::istream& in, const std::string& source) { return std::bit_cast<double>(read_u64(in, source)); }

std::uint64_t bytes_left(std::istream& in) {
  const auto pos = in.tellg();
  if (pos < 0) return 0;
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(pos);
  return end < pos ? 0 : static_cast<std::uint64_t>(end - pos);
}

std::uint64_t read_count(std::istream& in, std::uint64_t item_bytes, const std::string& source) {
  const std::uint64_t n = read_u64(in, source);
  if (item_bytes > 0 && n > bytes_left(in) / item_bytes) throw Error(source + ": file is truncated or damaged (a count of " + std::to_string(n) + " does not fit in it)");
  return n;
}

std::string read_string(std::istream& in, const std::string& source) {
  const std::uint64_t n = read_count(in, 1, source);
  std::string s(n, '\0');
  read_bytes(in, s.data(), n, source);
  return s;
}

}  // namespace rdsim
