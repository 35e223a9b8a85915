#include "rdsim/remote/request.hpp"

#include <climits>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/remote/message.hpp"
#include "rdsim/remote/protocol.hpp"

namespace rdsim::remote {
namespace {

constexpr long long kMaxId = 1LL << 53;  // exact in every JSON implementation's numbers

const std::vector<std::pair<const char*, RequestKind>>& kinds() {
  static const std::vector<std::pair<const char*, RequestKind>> k = {
      {"hello", RequestKind::Hello},   {"reset", RequestKind::Reset},     {"step", RequestKind::Step},
      {"position", RequestKind::Position}, {"joints", RequestKind::Joints}, {"cameras", RequestKind::Cameras},
      {"state", RequestKind::State},   {"drop_caches", RequestKind::DropCaches}, {"close", RequestKind::Close}};
  return k;
}

void require(ConfigReader& r, const char* key, const char* what) {
  if (!r.has(key)) r.fail(key, std::string("missing: expected ") + what);
}

std::vector<float> read_vector(ConfigReader& r, const char* key) {
  std::vector<double> v;
  r.read(key, v, -max_vector_value, max_vector_value);
  if (v.size() > static_cast<std::size_t>(max_vector_size))
    r.fail(key, "expected at most " + std::to_string(max_vector_size) + " numbers, got " + std::to_string(v.size()));
  return std::vector<float>(v.begin(), v.end());
}

void read_body(ConfigReader& r, const nlohmann::json& header, Request& q) {
  switch (q.kind) {
    case RequestKind::Hello: {
      require(r, "protocol", "the protocol version (an integer)");
      r.read("protocol", q.protocol, INT_MIN, INT_MAX);
      if (q.protocol != protocol_version)
        r.fail("protocol", "this server speaks protocol " + std::to_string(protocol_version) + ", the client " +
                               std::to_string(q.protocol));
      require(r, "env", "an object such as {\"name\": \"jaka_button\"}");
      (void)r.child("env");  // checks that it is an object
      q.env = header["env"];
      break;
    }
    case RequestKind::Reset:
      if (r.has("seed")) {
        std::uint64_t seed = 0;
        r.read("seed", seed);
        q.seed = seed;
      }
      break;
    case RequestKind::Step: {
      require(r, "action", "an integer (Discrete) or a list of numbers (Box)");
      if (header["action"].is_array()) {
        q.action_values = read_vector(r, "action");
      } else {
        int index = 0;
        r.read("action", index, INT_MIN, INT_MAX);
        q.action_index = index;
      }
      break;
    }
    case RequestKind::Position: {
      require(r, "position", "[x, y, z] in metres");
      const std::vector<float> p = read_vector(r, "position");
      if (p.size() != 3) r.fail("position", "expected [x, y, z], got " + std::to_string(p.size()) + " numbers");
      q.position = Eigen::Vector3f(p[0], p[1], p[2]);
      break;
    }
    case RequestKind::Joints:
      require(r, "joints", "a list with one target per joint");
      q.joints = read_vector(r, "joints");
      break;
    case RequestKind::Cameras: {
      require(r, "width", "the image width in pixels");
      require(r, "height", "the image height in pixels");
      r.read("width", q.width, 1, max_camera_side);
      r.read("height", q.height, 1, max_camera_side);
      if (r.has("cameras")) {
        r.accept("cameras");
        const nlohmann::json& names = header["cameras"];
        if (!names.is_array() || names.size() > 8)
          r.fail("cameras", "expected a list of at most 8 camera names");
        for (const auto& n : names) {
          if (!n.is_string() || n.get_ref<const std::string&>().size() > 64)
            r.fail("cameras", "expected camera names (strings)");
          q.cameras.push_back(n.get<std::string>());
        }
      }
      break;
    }
    case RequestKind::State:
    case RequestKind::DropCaches:
    case RequestKind::Close: break;
  }
}

}  // namespace

const char* to_string(RequestKind kind) {
  for (const auto& [name, k] : kinds())
    if (k == kind) return name;
  return "?";
}

ParsedRequest parse_request(const std::vector<std::string_view>& frames) {
  ParsedRequest out;
  out.id = nullptr;
  try {
    const Message m = decode_message(frames, max_request_frame_bytes, max_request_frame_bytes);
    if (!m.arrays.empty()) throw Error("requests carry no arrays (vectors are JSON lists)");
    ConfigReader top(m.header, "request");
    require(top, "id", "an integer that the reply repeats");
    Request q;
    top.read("id", q.id, 0, kMaxId);
    out.id = q.id;
    require(top, "request", "one of hello, reset, step, position, joints, cameras, state, drop_caches, close");
    std::string name;
    static const std::vector<std::string> names = [] {  // built once, not per request
      std::vector<std::string> v;
      for (const auto& [n, k] : kinds()) v.emplace_back(n);
      return v;
    }();
    top.read_choice("request", name, names);
    for (const auto& [n, k] : kinds())
      if (name == n) q.kind = k;
    ConfigReader body(m.header, name);
    body.accept("id");
    body.accept("request");
    read_body(body, m.header, q);
    body.finish();
    out.request = std::move(q);
  } catch (const Error& e) {
    out.error = e.what();
  }
  return out;
}

}  // namespace rdsim::remote
