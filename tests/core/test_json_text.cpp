// Bounded, strict JSON reading (core/json_text.hpp): every limit is an rdsim::Error naming the
// source, checked before anything deep or large is built.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/core/json_text.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

std::string error_of(const std::string& text, std::uint64_t max_bytes = rdsim::max_config_bytes) {
  try {
    rdsim::parse_json(text, "cfg.json", max_bytes);
  } catch (const rdsim::Error& e) {
    return e.what();
  }
  return "";
}

std::string nested(int depth) { return std::string(static_cast<size_t>(depth), '[') + std::string(static_cast<size_t>(depth), ']'); }

}  // namespace

TEST_CASE("parse_json reads valid JSON and rejects the rest with one line naming the source", "[json]") {
  CHECK(rdsim::parse_json(R"({"a": [1, 2, {"b": null}]})", "cfg.json")["a"][2].contains("b"));
  for (const char* bad : {"", "{", "[1,]", "{\"a\": tru}", "NaN", "{\"a\": Infinity}", "{\"a\": 01}", "// c\n{}"}) {
    INFO(bad);
    const std::string e = error_of(bad);
    CHECK_THAT(e, StartsWith("cfg.json: not valid JSON"));
    CHECK(e.find('\n') == std::string::npos);
  }
}

TEST_CASE("parse_json: nesting deeper than the limit is refused before parsing", "[json]") {
  CHECK_NOTHROW(rdsim::parse_json(nested(rdsim::max_json_depth), "cfg.json"));
  CHECK_THAT(error_of(nested(rdsim::max_json_depth + 1)), Contains("nested more than 64"));
  // The depth that used to overflow the stack when the value was printed back.
  CHECK_THAT(error_of("{\"a\": " + nested(100000) + "}"), Contains("cfg.json") && Contains("line 1"));
  // Brackets inside strings do not count.
  CHECK_NOTHROW(rdsim::parse_json("{\"a\": \"" + std::string(1000, '[') + "\"}", "cfg.json"));
}

TEST_CASE("parse_json: duplicate keys are an error naming the key path", "[json]") {
  CHECK_THAT(error_of(R"({"seed": 1, "seed": 2})"), Contains("cfg.json: seed: duplicate key"));
  CHECK_THAT(error_of(R"({"ppo": {"n_steps": 1, "gamma": 0.9, "n_steps": 2}})"), Contains("ppo.n_steps: duplicate key"));
  // The same key in sibling objects is fine.
  CHECK_NOTHROW(rdsim::parse_json(R"({"a": {"x": 1}, "b": {"x": 2}, "c": [{"x": 1}, {"x": 2}]})", "cfg.json"));
}

TEST_CASE("parse_json: numbers beyond double range and oversized text are errors", "[json]") {
  CHECK_THAT(error_of(R"({"lr": 1e400})"), Contains("cfg.json") && Contains("1e400"));
  CHECK_THAT(error_of(R"({"lr": -1e400})"), Contains("cfg.json"));
  CHECK_THAT(error_of(std::string(100, ' ') + "{}", 50), Contains("more than the 50 bytes"));
  // A long bad token is cut in the message, which stays one line.
  const std::string e = error_of("{\"a\": \"" + std::string(100000, 'x') + "\n");
  CHECK(e.size() < 600);
  CHECK(e.find('\n') == std::string::npos);
}

TEST_CASE("json_excerpt is short, one line and safe on huge or deep values", "[json]") {
  CHECK(rdsim::json_excerpt(nlohmann::json{{"a", 1}}) == R"({"a":1})");
  CHECK(rdsim::json_excerpt(nlohmann::json("line\nbreak")) == R"("line\nbreak")");
  nlohmann::json big = nlohmann::json::array();
  for (int i = 0; i < 100000; ++i) big.push_back(i);
  const std::string e = rdsim::json_excerpt(big, 60);
  CHECK(e.size() <= 63);
  CHECK_THAT(e, StartsWith("[0,1,2,"));
  // 200,000 levels deep (built by hand: the parser refuses such text).
  nlohmann::json deep = 1;
  for (int i = 0; i < 200000; ++i) deep = nlohmann::json::array({std::move(deep)});
  CHECK(rdsim::json_excerpt(deep, 20).size() <= 23);
  CHECK(rdsim::json_excerpt(nlohmann::json(std::string(1 << 20, 'x')), 30).size() <= 33);
  // The fuzzer's finding: a cut through a two-byte character (U+073C) made the excerpt throw.
  std::string syriac;
  for (int i = 0; i < 40; ++i) syriac += "\xdc\xbc";
  for (std::size_t cut : {7, 30, 31, 200}) {
    std::string e;
    REQUIRE_NOTHROW(e = rdsim::json_excerpt(nlohmann::json(syriac), cut));
    CHECK_NOTHROW(nlohmann::json(e).dump());  // valid UTF-8: it can go into a JSON reply
    CHECK(e.size() <= cut + 3);
  }
}

TEST_CASE("one_line escapes control characters and cuts long text", "[json]") {
  CHECK(rdsim::one_line("a\nb\tc") == "a\\x0Ab\\x09c");
  CHECK(rdsim::one_line("caf\xc3\xa9") == "caf\xc3\xa9");  // UTF-8 stays
  CHECK(rdsim::one_line("bad \xff byte") == "bad \\xFF byte");
  CHECK(rdsim::one_line(std::string(1000, 'x'), 10) == "xxxxxxxxxx...");
}
