#include "rdsim/core/model_envelope.hpp"

#include <cstring>

#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"

namespace rdsim {
namespace {

constexpr char magic[8] = {'R', 'D', 'S', 'I', 'M', 'M', 'D', 'L'};

template <class T>
void put(std::string& out, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  out.append(bytes, sizeof(T));
}

void put_block(std::string& out, const std::string& block) {
  put<std::uint64_t>(out, block.size());
  out += block;
}

// Reads fixed-size fields front to back; running past the end means the file was cut short.
struct Cursor {
  std::string_view bytes;
  std::size_t pos = 0;
  const std::string& source;

  template <class T>
  T get() {
    if (bytes.size() - pos < sizeof(T)) throw Error(source + ": file is truncated (not a complete rdsim model)");
    T v;
    std::memcpy(&v, bytes.data() + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  std::string_view block() {
    const auto n = get<std::uint64_t>();
    if (bytes.size() - pos < n) throw Error(source + ": file is truncated (not a complete rdsim model)");
    std::string_view s = bytes.substr(pos, n);
    pos += n;
    return s;
  }
};

}  // namespace

std::string encode_model_envelope(const ModelEnvelope& e) {
  std::string out(magic, sizeof magic);
  put<std::uint32_t>(out, model_format_version);
  put<std::uint32_t>(out, e.kind);
  put_block(out, e.config);
  put_block(out, e.spec);
  put_block(out, e.payload);
  put_block(out, e.policy);
  put<std::uint64_t>(out, fnv1a64(out));
  return out;
}

ModelEnvelope decode_model_envelope(std::string_view bytes, const std::string& source) {
  if (bytes.size() < sizeof magic || std::memcmp(bytes.data(), magic, sizeof magic) != 0) {
    throw Error(source + ": not an rdsim model file (wrong magic bytes; expected a model.bin or "
                         "checkpoint.bin written by `rdsim train`)");
  }
  Cursor c{bytes, sizeof magic, source};
  ModelEnvelope e;
  e.version = c.get<std::uint32_t>();
  if (e.version < 1 || e.version > model_format_version) {
    throw Error(source + ": model format version " + std::to_string(e.version) +
                " is not supported (this rdsim reads versions 1 to " + std::to_string(model_format_version) + ")");
  }
  e.kind = c.get<std::uint32_t>();
  e.config = std::string(c.block());
  if (e.version >= 3) e.spec = std::string(c.block());
  e.payload = std::string(c.block());
  if (e.version >= 4) e.policy = std::string(c.block());
  const std::size_t body = c.pos;
  const auto checksum = c.get<std::uint64_t>();
  if (c.pos != bytes.size()) throw Error(source + ": file is damaged (unexpected bytes after the checksum)");
  if (checksum != fnv1a64(bytes.substr(0, body))) throw Error(source + ": file is damaged (checksum mismatch)");
  if (e.kind > 1) throw Error(source + ": file is damaged (unknown kind " + std::to_string(e.kind) + ")");
  return e;
}

ModelEnvelope read_model_envelope(const std::string& path) {
  InputFile file(path, max_model_file_bytes);  // a regular file (input_file.hpp)
  // The magic bytes before the body: a large foreign file is refused without reading it.
  std::string bytes = file.read(sizeof magic);
  if (bytes.size() == sizeof magic && std::memcmp(bytes.data(), magic, sizeof magic) == 0) bytes += file.read_rest();
  return decode_model_envelope(bytes, path);
}

}  // namespace rdsim
