#include <catch2/catch.hpp>
#include <functional>
#include <nlohmann/json.hpp>

#include "../error_of.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/error.hpp"

using rdsim::ConfigReader;
using Catch::Matchers::Contains;
using rdsim::test::error_of;

TEST_CASE("config reader fills typed fields and keeps defaults for absent keys", "[config]") {
  auto j = nlohmann::json::parse(R"({"a": 3, "b": 0.5, "c": true, "s": "x", "v": [1, 2]})");
  ConfigReader r(j, "cfg.json");
  int a = 0, untouched = 7;
  double b = 0;
  bool c = false;
  std::string s;
  std::vector<int> v;
  r.read("a", a, 0, 10);
  r.read("b", b, 0.0, 1.0);
  r.read("c", c);
  r.read("s", s);
  r.read("v", v, 0, 5);
  r.read("absent", untouched, 0, 10);
  r.finish();
  CHECK(a == 3);
  CHECK(b == 0.5);
  CHECK(c);
  CHECK(s == "x");
  CHECK(v == std::vector<int>{1, 2});
  CHECK(untouched == 7);
}

TEST_CASE("config reader errors name the file and the key path", "[config]") {
  auto j = nlohmann::json::parse(R"({"env": {"max_steps": -3}, "lr": "fast", "typo": 1})");
  SECTION("out of range") {
    ConfigReader r(j, "cfg.json");
    auto env = r.child("env");
    int steps = 0;
    auto msg = error_of([&] { env.read("max_steps", steps, 1, 1000); });
    CHECK_THAT(msg, Contains("cfg.json") && Contains("env.max_steps") && Contains("[1, 1000]"));
  }
  SECTION("wrong type") {
    ConfigReader r(j, "cfg.json");
    double lr = 0;
    CHECK_THAT(error_of([&] { r.read("lr", lr, 0.0, 1.0); }), Contains("lr") && Contains("number"));
  }
  SECTION("unknown key") {
    ConfigReader r(j, "cfg.json");
    r.accept("env");
    r.accept("lr");
    CHECK_THAT(error_of([&] { r.finish(); }), Contains("typo") && Contains("unknown key"));
  }
}

TEST_CASE("config reader: integers are read exactly, whatever number form they come in", "[config]") {
  auto j = nlohmann::json::parse(R"({"a": 1e5, "b": 2.5, "c": 1e300, "d": -1e300, "e": 18446744073709551615,
                                     "f": [1, 2.0, 3e2], "g": [1, 1e300], "u": -1, "v": 1.5})");
  ConfigReader r(j, "cfg.json");
  long long a = 0, x = 0;
  r.read("a", a, 0LL, 1'000'000LL);
  CHECK(a == 100000);
  for (const char* key : {"b", "c", "d", "e"}) {
    INFO(key);
    CHECK_THAT(error_of([&] { r.read(key, x, 0LL, 1'000'000'000'000LL); }), Contains(std::string("cfg.json: ") + key) && Contains("[0, 1e12]"));
  }
  std::vector<int> f;
  r.read("f", f, 0, 1000);
  CHECK(f == std::vector<int>{1, 2, 300});
  CHECK_THAT(error_of([&] { r.read("g", f, 0, 1000); }), Contains("cfg.json: g") && Contains("1e+300"));
  std::uint64_t seed = 0;
  CHECK_THAT(error_of([&] { r.read("u", seed); }), Contains("[0, 2^64 - 1]") && Contains("got -1"));
  CHECK_THAT(error_of([&] { r.read("v", seed); }), Contains("got 1.5"));
  r.read("e", seed);
  CHECK(seed == 18446744073709551615ull);
}

TEST_CASE("config reader: ranges read well, lists and strings are bounded", "[config]") {
  auto j = nlohmann::json::parse(R"({"n": 0, "s": "a\nb", "t": "ok"})");
  j["long"] = std::string(5000, 'x');
  j["list"] = std::vector<int>(300, 1);
  ConfigReader r(j, "cfg.json");
  long long n = 1;
  CHECK_THAT(error_of([&] { r.read("n", n, 1LL, 100'000'000LL); }), Contains("in [1, 1e8], got 0"));
  std::string s;
  CHECK_THAT(error_of([&] { r.read("s", s); }), Contains("without control characters") && Contains("\"a\\nb\""));
  CHECK_THAT(error_of([&] { r.read("long", s); }), Contains("at most 4096 bytes"));
  r.read("t", s);
  CHECK(s == "ok");
  std::vector<int> list;
  CHECK_THAT(error_of([&] { r.read("list", list, 0, 10); }), Contains("at most 256"));
}

TEST_CASE("config reader: lists of strings, each checked as one string", "[config]") {
  const auto j = nlohmann::json::parse(R"({"names": ["joint_1", "joint_2"], "empty": [], "mixed": ["a", 3],
                                           "ctrl": ["a\nb"], "not_list": "a"})");
  ConfigReader r(j, "cfg.json");
  std::vector<std::string> names, empty = {"kept?"}, absent = {"default"};
  r.read("names", names);
  r.read("empty", empty);
  r.read("absent", absent);
  CHECK(names == std::vector<std::string>{"joint_1", "joint_2"});
  CHECK(empty.empty());
  CHECK(absent == std::vector<std::string>{"default"});
  for (const char* key : {"mixed", "ctrl", "not_list"}) {
    std::vector<std::string> out;
    CHECK_THAT(error_of([&] { r.read(key, out); }),
               Contains(std::string("cfg.json: ") + key + ": expected a list of at most 256 strings of at most 4096 bytes"));
  }
}
