#include "rdsim/training/model_file.hpp"

#include <cstring>
#include <filesystem>

#include "rdsim/training/train_config.hpp"
#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/input_file.hpp"
#include "rdsim/core/json_text.hpp"

namespace rdsim {
namespace {

constexpr char magic[8] = {'R', 'D', 'S', 'I', 'M', 'M', 'D', 'L'};

template <class T>
void put(std::string& out, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  out.append(bytes, sizeof(T));
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

std::string encode_model_file(const ModelFile& file) {
  const std::string config = file.config.dump();
  std::string out(magic, sizeof magic);
  put<std::uint32_t>(out, model_format_version);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(file.kind));
  put<std::uint64_t>(out, config.size());
  out += config;
  put<std::uint64_t>(out, file.spec.size());
  out += file.spec;
  put<std::uint64_t>(out, file.payload.size());
  out += file.payload;
  put<std::uint64_t>(out, fnv1a64(out));
  return out;
}

ModelFile decode_model_file(std::string_view bytes, const std::string& source) {
  if (bytes.size() < sizeof magic || std::memcmp(bytes.data(), magic, sizeof magic) != 0) {
    throw Error(source + ": not an rdsim model file (wrong magic bytes; expected a model.bin or "
                         "checkpoint.bin written by `rdsim train`)");
  }
  Cursor c{bytes, sizeof magic, source};
  const auto version = c.get<std::uint32_t>();
  if (version < 1 || version > model_format_version) {
    throw Error(source + ": model format version " + std::to_string(version) + " is not supported (this rdsim reads versions 1 to " +
                std::to_string(model_format_version) + ")");
  }
  const auto kind = c.get<std::uint32_t>();
  const std::string_view config = c.block();
  const std::string_view spec = version >= 3 ? c.block() : std::string_view();
  const std::string_view payload = c.block();
  const std::size_t body = c.pos;
  const auto checksum = c.get<std::uint64_t>();
  if (c.pos != bytes.size()) throw Error(source + ": file is damaged (unexpected bytes after the checksum)");
  if (checksum != fnv1a64(bytes.substr(0, body))) throw Error(source + ": file is damaged (checksum mismatch)");
  if (kind > 1) throw Error(source + ": file is damaged (unknown kind " + std::to_string(kind) + ")");
  ModelFile file;
  file.kind = static_cast<ModelKind>(kind);
  file.config = parse_json(config, source + " (embedded config)");
  if (!file.config.is_object()) throw Error(source + ": file is damaged (its embedded config is not a JSON object)");
  if (version == 1) upgrade_v1_config(file.config);
  file.spec = std::string(spec);
  file.payload = std::string(payload);
  return file;
}

std::string describe_spec(const Spec& spec) {
  std::string s = spec.env_name + ": observation " + (spec.observation.type == ObsType::UInt8 ? "uint8 {" : "float32 {");
  for (std::size_t i = 0; i < spec.observation.shape.size(); ++i)
    s += (i ? ", " : "") + std::to_string(spec.observation.shape[i]);
  s += "}, actions ";
  s += spec.action.discrete ? "discrete " + std::to_string(spec.action.n) : "box " + std::to_string(spec.action.dim());
  return s;
}

void check_model_spec(const ModelFile& file, const Spec& spec, const std::string& source) {
  if (file.spec.empty() || file.spec == describe_spec(spec)) return;
  throw Error(source + ": file is damaged or edited: its weights were trained on \"" + one_line(file.spec, 120) +
              "\" but its config builds \"" + describe_spec(spec) + "\"");
}

void write_model_file(const std::string& path, const ModelFile& file) { write_file_atomic(path, encode_model_file(file)); }

ModelFile read_model_file(const std::string& path) {
  InputFile file(path, max_model_file_bytes);  // a regular file (input_file.hpp)
  // The magic bytes before the body: a large foreign file is refused without reading it.
  std::string bytes = file.read(sizeof magic);
  if (bytes.size() < sizeof magic || std::memcmp(bytes.data(), magic, sizeof magic) != 0) return decode_model_file(bytes, path);
  bytes += file.read_rest();
  return decode_model_file(bytes, path);
}

}  // namespace rdsim
