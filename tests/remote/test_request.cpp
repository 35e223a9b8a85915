// The wire format (message.hpp) and the pure request parser (request.hpp): every malformed input
// becomes an error message, never an exception, a crash or a large allocation.
#include <catch2/catch.hpp>

#include <random>

#include "rdsim/core/error.hpp"
#include "rdsim/remote/message.hpp"
#include "rdsim/remote/protocol.hpp"
#include "rdsim/remote/request.hpp"

using namespace rdsim;
using namespace rdsim::remote;
using Catch::Matchers::Contains;

namespace {

ParsedRequest parse(const std::string& header, std::vector<std::string> extra = {}) {
  std::vector<std::string_view> frames = {header};
  for (const auto& e : extra) frames.emplace_back(e);
  return parse_request(frames);
}

std::string error_of(const std::string& header, std::vector<std::string> extra = {}) {
  const ParsedRequest p = parse(header, std::move(extra));
  CHECK_FALSE(p.request);
  return p.error;
}

}  // namespace

TEST_CASE("message: arrays travel as raw frames and come back bit for bit", "[remote][message]") {
  Message m;
  m.header["reply"] = "step";
  const float values[3] = {1.5f, -0.0f, 3.4028235e38f};
  const std::uint8_t pixels[12] = {0, 1, 2, 3, 4, 5, 250, 251, 252, 253, 254, 255};
  m.arrays.push_back(ArrayFrame::float32("observation", values, {3}));
  m.arrays.push_back(ArrayFrame::uint8("image", pixels, {2, 2, 3}));
  const std::vector<std::string> frames = encode_message(m);
  REQUIRE(frames.size() == 3);
  CHECK(frames[1].size() == 12);
  CHECK(frames[0].find("\"dtype\":\"uint8\"") != std::string::npos);
  const std::vector<std::string_view> views(frames.begin(), frames.end());
  const Message back = decode_message(views, 1 << 16, 1 << 16);
  CHECK(back.header["reply"] == "step");
  CHECK_FALSE(back.header.contains("arrays"));
  REQUIRE(back.find("observation"));
  CHECK(back.find("observation")->floats() == std::vector<float>(values, values + 3));
  CHECK(back.find("image")->shape == std::vector<int>{2, 2, 3});
  CHECK(back.find("image")->bytes == std::string(reinterpret_cast<const char*>(pixels), 12));
}

TEST_CASE("message: the header text is valid JSON whatever the header holds", "[remote][message]") {
  const std::uint8_t byte = 7;
  Message empty;  // "{}" before the arrays list is appended
  empty.arrays.push_back(ArrayFrame::uint8("b", &byte, {1}));
  CHECK(nlohmann::json::parse(encode_header(empty)) ==
        nlohmann::json::parse(R"({"arrays": [{"name": "b", "dtype": "uint8", "shape": [1]}]})"));
  Message stale = empty;  // an "arrays" key already there is replaced, not repeated
  stale.header["arrays"] = 1;
  stale.header["id"] = 3;
  const nlohmann::json parsed = nlohmann::json::parse(encode_header(stale));
  CHECK(parsed["arrays"].size() == 1);
  CHECK(parsed["id"] == 3);
  Message plain;  // no arrays: the header as it is
  plain.header["id"] = 4;
  CHECK(encode_header(plain) == R"({"id":4})");
}

TEST_CASE("message: frames that disagree with the header are refused", "[remote][message]") {
  auto decode = [](std::vector<std::string> frames) {
    const std::vector<std::string_view> views(frames.begin(), frames.end());
    return decode_message(views, 1 << 16, 1 << 16);
  };
  const std::string one = R"({"arrays": [{"name": "a", "dtype": "float32", "shape": [2]}]})";
  CHECK_NOTHROW(decode({one, std::string(8, '\0')}));
  CHECK_THROWS_WITH(decode({one, std::string(7, '\0')}), Contains("frame of 7 bytes, its shape needs 8"));
  CHECK_THROWS_WITH(decode({one}), Contains("declares 1 arrays, so 2 expected"));
  CHECK_THROWS_WITH(decode({one, "12345678", "x"}), Contains("3 frames"));
  CHECK_THROWS_WITH(decode({R"({"arrays": [{"name": "a", "dtype": "float64", "shape": [1]}]})", "12345678"}),
                    Contains("dtype"));
  CHECK_THROWS_WITH(decode({R"({"arrays": [{"name": "a", "dtype": "uint8", "shape": [4294967296, 4294967296]}]})", "x"}),
                    Contains("too many elements"));
  CHECK_THROWS_WITH(decode({R"({"arrays": [{"name": "a", "dtype": "uint8", "shape": [-1]}]})", ""}), Contains("shape"));
  CHECK_THROWS_WITH(decode({R"({"arrays": 5})"}), Contains("arrays"));
  CHECK_THROWS_WITH(decode({"[1, 2]"}), Contains("expected a JSON object"));
  CHECK_THROWS_WITH(decode({"{\"a\": "}), Contains("not valid JSON"));
  CHECK_THROWS_WITH(decode({}), Contains("empty message"));
  CHECK_THROWS_WITH(decode(std::vector<std::string>(17, "{}")), Contains("at most 16"));
  CHECK_THROWS_WITH(decode({std::string(70000, ' ')}), Contains("at most 65536"));
}

TEST_CASE("message: nesting depth is counted without parsing, strings skipped", "[remote][message]") {
  CHECK(json_depth("{}") == 1);
  CHECK(json_depth(R"({"a": [[1], {"b": []}]})") == 4);
  CHECK(json_depth(R"({"a": "[[[[[[[[[[\"]]]"})") == 1);
  CHECK(json_depth(std::string(100000, '[')) == 100000);
  const std::string deep = std::string(9, '[') + std::string(9, ']');
  CHECK_THAT(error_of(deep), Contains("nested deeper than 8"));
}

TEST_CASE("request: each kind parses into its typed fields", "[remote][request]") {
  ParsedRequest p = parse(R"({"id": 1, "request": "hello", "protocol": 1, "env": {"name": "jaka_button"}})");
  REQUIRE(p.request);
  CHECK(p.request->kind == RequestKind::Hello);
  CHECK(p.request->env["name"] == "jaka_button");
  p = parse(R"({"id": 2, "request": "reset", "seed": 18446744073709551615})");
  REQUIRE(p.request);
  CHECK(*p.request->seed == 18446744073709551615ull);
  p = parse(R"({"id": 3, "request": "reset"})");
  REQUIRE(p.request);
  CHECK_FALSE(p.request->seed);
  p = parse(R"({"id": 4, "request": "step", "action": 5})");
  REQUIRE(p.request);
  CHECK(*p.request->action_index == 5);
  p = parse(R"({"id": 5, "request": "step", "action": [0.25, -1, 1e-3]})");
  REQUIRE(p.request);
  CHECK(p.request->action_values == std::vector<float>{0.25f, -1.0f, 1e-3f});
  p = parse(R"({"id": 6, "request": "position", "position": [0.5, 0, 0.1]})");
  REQUIRE(p.request);
  CHECK(p.request->position == Eigen::Vector3f(0.5f, 0.0f, 0.1f));
  p = parse(R"({"id": 7, "request": "joints", "joints": [0, 1, 2]})");
  REQUIRE(p.request);
  CHECK(p.request->joints.size() == 3);
  p = parse(R"({"id": 8, "request": "cameras", "width": 224, "height": 100, "cameras": ["wrist"]})");
  REQUIRE(p.request);
  CHECK(p.request->width == 224);
  CHECK(p.request->cameras == std::vector<std::string>{"wrist"});
  for (const char* kind : {"state", "close"}) {
    p = parse(std::string(R"({"id": 9, "request": ")") + kind + "\"}");
    REQUIRE(p.request);
    CHECK(to_string(p.request->kind) == std::string(kind));
  }
}

TEST_CASE("request: bad requests get one clear message and keep their id", "[remote][request]") {
  CHECK_THAT(error_of(R"({"request": "reset"})"), Contains("id: missing"));
  CHECK_THAT(error_of(R"({"id": -1, "request": "reset"})"), Contains("id: expected an integer"));
  CHECK_THAT(error_of(R"({"id": 1e300, "request": "reset"})"), Contains("id: expected an integer"));
  CHECK_THAT(error_of(R"({"id": 18446744073709551615, "request": "reset"})"), Contains("id: expected an integer"));
  ParsedRequest p = parse(R"({"id": 12, "request": "jump"})");
  CHECK(p.id == 12);
  CHECK_THAT(p.error, Contains("request: expected one of \"hello\", \"reset\""));
  CHECK_THAT(error_of(R"({"id": 1, "request": "hello", "protocol": 2, "env": {}})"),
             Contains("hello: protocol: this server speaks protocol 1, the client 2"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "hello", "env": {}})"), Contains("hello: protocol: missing"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "hello", "protocol": 1, "env": 3})"), Contains("hello: env: expected a JSON object"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step"})"), Contains("step: action: missing"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": "up"})"), Contains("step: action: expected an integer"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": 2.5})"), Contains("step: action: expected an integer"));
  // Non-finite numbers: JSON has none (NaN is not JSON; 1e999 does not parse), and magnitudes
  // that a float cannot hold are refused.
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": [NaN, 0, 0]})"), Contains("not valid JSON"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": [1e999, 0, 0]})"), Contains("not valid JSON"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": [1e300, 0, 0]})"), Contains("step: action: expected a list of at most"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": [1, "a"]})"), Contains("step: action: expected a list of at most"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "step", "action": 1, "extra": 2})"), Contains("step: extra: unknown key"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "position", "position": [1, 2]})"), Contains("expected [x, y, z]"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "cameras", "width": 100000, "height": 10})"),
             Contains("cameras: width: expected an integer in [1, 1024]"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "cameras", "width": 10, "height": 10, "cameras": [1]})"),
             Contains("camera names"));
  std::string big = R"({"id": 1, "request": "joints", "joints": [0)";
  for (int i = 0; i < 300; ++i) big += ",0";
  CHECK_THAT(error_of(big + "]}"), Contains("at most 256 numbers"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "state"})", {"x"}), Contains("2 frames"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "state", "arrays": [{"name": "a", "dtype": "uint8", "shape": [1]}]})", {"x"}),
             Contains("requests carry no arrays"));
}

TEST_CASE("request: random and mutated bytes never escape the parser", "[remote][request]") {
  std::mt19937 gen(1);
  const std::vector<std::string> valid = {
      R"({"id": 1, "request": "hello", "protocol": 1, "env": {"name": "jaka_button", "max_steps": 50}})",
      R"({"id": 2, "request": "step", "action": [0.5, 0.25, -1]})",
      R"({"id": 3, "request": "cameras", "width": 64, "height": 64, "cameras": ["wrist"]})"};
  for (int n = 0; n < 20000; ++n) {
    std::string s = valid[static_cast<size_t>(n) % valid.size()];
    switch (n % 4) {
      case 0: s.resize(gen() % (s.size() + 1)); break;
      case 1: s[gen() % s.size()] ^= static_cast<char>(1 << (gen() % 8)); break;
      case 2: s.insert(gen() % s.size(), 1, static_cast<char>(gen())); break;
      default:
        s.assign(gen() % 64, '\0');
        for (char& c : s) c = static_cast<char>(gen());
    }
    const ParsedRequest p = parse(s);
    CHECK((p.request.has_value() || !p.error.empty()));
  }
}

TEST_CASE("request: a key given twice is refused, as in config files", "[remote][request]") {
  // Before: the last one won: a second "request" turned a state request into a close, a second
  // env "name" opened another env than the first one named.
  CHECK_THAT(error_of(R"({"id": 1, "request": "state", "request": "close"})"),
             Contains("header: request: duplicate key (a key may appear only once in an object)"));
  CHECK_THAT(error_of(R"({"id": 1, "request": "hello", "protocol": 1, "env": {"name": "cartpole", "name": "jaka_button"}})"),
             Contains("env.name: duplicate key"));
  CHECK(parse(R"({"id": 1, "request": "state"})").request);  // one of each is fine
}
