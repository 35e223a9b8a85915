#include <catch2/catch.hpp>
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
