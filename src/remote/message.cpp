#include "rdsim/remote/message.hpp"

#include <algorithm>
#include <cstring>

#include "rdsim/core/error.hpp"
#include "rdsim/core/json_text.hpp"
#include "rdsim/remote/protocol.hpp"

namespace rdsim::remote {
namespace {

constexpr int kMaxDims = 4;
constexpr long long kMaxElements = 1LL << 32;

ArrayFrame make_frame(std::string name, DType dtype, const void* data, std::vector<int> shape) {
  ArrayFrame f;
  f.name = std::move(name);
  f.dtype = dtype;
  f.shape = std::move(shape);
  f.bytes.assign(static_cast<const char*>(data), f.count() * element_size(dtype));
  return f;
}

[[noreturn]] void fail(const std::string& what) { throw Error(what); }

ArrayFrame read_declaration(const nlohmann::json& d, std::size_t index) {
  const std::string where = "arrays[" + std::to_string(index) + "]";
  if (!d.is_object()) fail(where + ": expected an object {\"name\", \"dtype\", \"shape\"}");
  ArrayFrame f;
  const auto name = d.find("name"), dtype = d.find("dtype"), shape = d.find("shape");
  if (name == d.end() || !name->is_string() || name->get_ref<const std::string&>().size() > 64)
    fail(where + ".name: expected a string of at most 64 characters");
  if (dtype == d.end() || !dtype->is_string()) fail(where + ".dtype: expected \"float32\" or \"uint8\"");
  if (*dtype == "float32") f.dtype = DType::Float32;
  else if (*dtype == "uint8") f.dtype = DType::UInt8;
  else fail(where + ".dtype: expected \"float32\" or \"uint8\"");
  if (shape == d.end() || !shape->is_array() || shape->size() > kMaxDims)
    fail(where + ".shape: expected a list of at most " + std::to_string(kMaxDims) + " sizes");
  long long count = 1;
  for (const auto& s : *shape) {
    if (!s.is_number_integer() || s.get<long long>() < 0 || s.get<long long>() > kMaxElements)
      fail(where + ".shape: expected non-negative integer sizes");
    const long long size = s.get<long long>();
    if (size != 0 && count > kMaxElements / size) fail(where + ".shape: too many elements");
    count *= size;
    f.shape.push_back(static_cast<int>(s.get<long long>()));
  }
  if (d.size() != 3) fail(where + ": expected exactly the keys name, dtype, shape");
  f.name = name->get<std::string>();
  return f;
}

}  // namespace

ArrayFrame ArrayFrame::float32(std::string name, const float* data, std::vector<int> shape) {
  return make_frame(std::move(name), DType::Float32, data, std::move(shape));
}

ArrayFrame ArrayFrame::uint8(std::string name, const std::uint8_t* data, std::vector<int> shape) {
  return make_frame(std::move(name), DType::UInt8, data, std::move(shape));
}

std::size_t ArrayFrame::count() const {
  std::size_t n = 1;
  for (int d : shape) n *= static_cast<std::size_t>(d);
  return n;
}

std::vector<float> ArrayFrame::floats() const {
  if (dtype != DType::Float32) fail("array " + name + ": expected float32, got " + to_string(dtype));
  std::vector<float> out(count());
  if (!out.empty()) std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  return out;
}

const ArrayFrame* Message::find(std::string_view name) const {
  for (const ArrayFrame& a : arrays)
    if (a.name == name) return &a;
  return nullptr;
}

const char* to_string(DType dtype) { return dtype == DType::UInt8 ? "uint8" : "float32"; }

std::size_t element_size(DType dtype) { return dtype == DType::UInt8 ? 1 : 4; }

// dump_json: invalid UTF-8 in a header (an error reply quoting a client's bytes) goes out as U+FFFD
// rather than throwing, so the peer always gets a well-formed reply.
std::string encode_header(const Message& m) {
  std::string text = dump_json(m.header);
  if (m.arrays.empty()) return text;
  nlohmann::json list = nlohmann::json::array();
  for (const ArrayFrame& a : m.arrays) list.push_back({{"name", a.name}, {"dtype", to_string(a.dtype)}, {"shape", a.shape}});
  if (m.header.contains("arrays") || text.size() < 2 || text.back() != '}') {  // not an object, or "arrays" to replace
    nlohmann::json header = m.header;
    header["arrays"] = std::move(list);
    return dump_json(header);
  }
  // Appended to the object's text rather than to a copy of the header: no copy of its values.
  text.pop_back();
  text += text.size() > 1 ? ",\"arrays\":" : "\"arrays\":";
  text += list.dump();
  text += '}';
  return text;
}

std::vector<std::string> encode_message(const Message& m) {
  std::vector<std::string> frames;
  frames.reserve(1 + m.arrays.size());
  frames.push_back(encode_header(m));
  for (const ArrayFrame& a : m.arrays) frames.push_back(a.bytes);
  return frames;
}

int json_depth(std::string_view text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') deepest = std::max(deepest, ++depth);
    else if (c == ']' || c == '}') --depth;
  }
  return deepest;
}

Message decode_message(const std::vector<std::string_view>& frames, std::size_t max_header_bytes,
                       std::size_t max_frame_bytes) {
  if (frames.empty()) fail("empty message: expected a JSON header frame");
  if (frames.size() > static_cast<std::size_t>(max_frames))
    fail("message has " + std::to_string(frames.size()) + " frames, at most " + std::to_string(max_frames) + " expected");
  const std::string_view text = frames[0];
  if (text.size() > max_header_bytes)
    fail("header of " + std::to_string(text.size()) + " bytes, at most " + std::to_string(max_header_bytes) + " expected");
  if (json_depth(text) > max_json_depth)
    fail("header nested deeper than " + std::to_string(max_json_depth) + " levels");
  Message m;
  // The config reader's parser: a key repeated in an object is refused exactly as in a config
  // file (a second "request" or env "name" must not silently win).
  try {
    m.header = parse_json(text, "header", max_header_bytes);
  } catch (const Error& e) {
    if (std::string_view(e.what()).find("duplicate key") != std::string_view::npos) fail(e.what());
    fail("header is not valid JSON");
  }
  if (!m.header.is_object()) fail("header: expected a JSON object, got " + std::string(m.header.type_name()));
  const auto arrays = m.header.find("arrays");
  if (arrays != m.header.end()) {
    if (!arrays->is_array() || arrays->size() >= static_cast<std::size_t>(max_frames))
      fail("arrays: expected a list of at most " + std::to_string(max_frames - 1) + " array descriptions");
    for (std::size_t i = 0; i < arrays->size(); ++i) m.arrays.push_back(read_declaration((*arrays)[i], i));
    m.header.erase(arrays);
  }
  if (frames.size() != 1 + m.arrays.size())
    fail("message has " + std::to_string(frames.size()) + " frames; its header declares " +
         std::to_string(m.arrays.size()) + " arrays, so " + std::to_string(1 + m.arrays.size()) + " expected");
  for (std::size_t i = 0; i < m.arrays.size(); ++i) {
    ArrayFrame& a = m.arrays[i];
    const std::size_t expected = a.count() * element_size(a.dtype);
    const std::string_view bytes = frames[i + 1];
    if (bytes.size() > max_frame_bytes || bytes.size() != expected)
      fail("array " + a.name + ": frame of " + std::to_string(bytes.size()) + " bytes, its shape needs " +
           std::to_string(expected));
    a.bytes.assign(bytes.begin(), bytes.end());
  }
  return m;
}

}  // namespace rdsim::remote
