// Envs own their options: every "env" key is declared once (core's describe_env_basics /
// describe_env_drawing, or one option group's describe()), and the keys the registry accepts for
// an env are exactly the union of the descriptions that env uses.
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <typeindex>
#include <vector>

#include "../error_of.hpp"
#include "rdsim/core/config_fields.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/reaching/button_options.hpp"
#include "rdsim/envs/manipulation/manipulation_options.hpp"
#include "rdsim/envs/reaching/obstacle_options.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/randomization.hpp"
#include "rdsim/envs/registry.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;
using rdsim::test::error_of;

namespace {

template <class Describe>
std::vector<std::string> keys_of(Describe&& describe_into) {
  std::vector<config::FieldDoc> rows;
  config::FieldDocs docs(rows);
  describe_into(docs);
  std::vector<std::string> keys;
  for (const auto& r : rows) keys.push_back(r.key);
  return keys;
}

std::vector<std::string> basics() {
  EnvConfig c;
  return keys_of([&](config::FieldDocs& d) { describe_env_basics(d, c); });
}
std::vector<std::string> drawing() {
  EnvConfig c;
  return keys_of([&](config::FieldDocs& d) { describe_env_drawing(d, c); });
}
template <class T>
std::vector<std::string> group() {
  const T t{};
  return keys_of([&](config::FieldDocs& d) { describe(d, t); });
}

std::set<std::string> set_of(std::vector<std::string> a) { return {a.begin(), a.end()}; }

// (The reader keeps a reference to `j`.)
ConfigReader reader_of(const nlohmann::json& j) { return ConfigReader(j, "x.json", "env"); }

}  // namespace

TEST_CASE("every env option key is declared exactly once", "[config][envs]") {
  // Core's two descriptions and every distinct option group any registered env uses.
  std::map<std::string, int> declared;
  for (const auto& k : basics()) ++declared[k];
  for (const auto& k : drawing()) ++declared[k];
  std::set<std::type_index> groups;
  for (const EnvEntry& e : env_registry())
    for (const EnvOptions& o : default_env_config(e.name).options)
      if (groups.insert(std::type_index(o.type())).second)
        for (const auto& row : o.document()) ++declared[row.key];
  for (const auto& [key, count] : declared) {
    INFO(key);
    CHECK(count == 1);
  }
  // The groups are the reaching tasks', the Jaka's button, the obstacle's, the arm (reach's and the
  // manipulation tasks'), the manipulation tasks' and every robot task's randomization (a new group
  // shows up here).
  CHECK(groups == std::set<std::type_index>{typeid(ReachOptions), typeid(ButtonOptions), typeid(ObstacleOptions),
                                            typeid(ArmOptions), typeid(ManipulationOptions), typeid(RandomizeOptions)});
}

TEST_CASE("the registry accepts for each env exactly the union of the descriptions it uses", "[config][envs]") {
  const auto core = set_of(basics());
  auto pixel_core = core;
  for (const auto& k : drawing()) pixel_core.insert(k);
  auto with = [](std::set<std::string> s, const std::vector<std::string>& more) {
    s.insert(more.begin(), more.end());
    return s;
  };
  // The manipulation tasks read the arm's keys without reach's target (ArmOptions::has_target).
  std::vector<std::string> arm = group<ArmOptions>();
  std::erase(arm, "target_centre");
  std::erase(arm, "target_half_range");
  const std::set<std::string> manipulation =
      with(with(with(pixel_core, group<ManipulationOptions>()), arm), std::vector<std::string>{"randomize"});
  // Every robot task also reads "randomize" (one object key).
  pixel_core.insert("randomize");
  const std::map<std::string, std::set<std::string>> expected = {
      {"cartpole", core},
      {"pendulum", core},
      {"jaka_button", with(with(pixel_core, group<ReachOptions>()), group<ButtonOptions>())},
      {"jaka_obstacle", with(with(with(pixel_core, group<ReachOptions>()), group<ButtonOptions>()), group<ObstacleOptions>())},
      {"inmoov_tomato", with(pixel_core, group<ReachOptions>())},
      {"reach", with(with(pixel_core, group<ReachOptions>()), group<ArmOptions>())},
      {"reach_goal", manipulation},
      {"push", manipulation},
      {"pick_and_place", manipulation},
      {"stack", manipulation},
  };
  std::set<std::string> every;
  for (const EnvEntry& e : env_registry()) {
    const auto keys = env_keys(e);
    every.insert(keys.begin(), keys.end());
  }
  CHECK(expected.size() == env_registry().size());
  for (const EnvEntry& e : env_registry()) {
    INFO(e.name);
    const std::vector<std::string> keys = env_keys(e);
    CHECK(keys.front() == "name");
    CHECK(set_of(keys).size() == keys.size());
    REQUIRE(expected.count(e.name) == 1);
    CHECK(set_of(keys) == expected.at(e.name));
    // The resolved config names exactly these keys and reads back to itself.
    const nlohmann::json json = to_json(default_env_config(e.name));
    std::set<std::string> written;
    for (auto it = json.begin(); it != json.end(); ++it) written.insert(it.key());
    CHECK(written == set_of(keys));
    ConfigReader back = reader_of(json);
    CHECK(to_json(read_env_config(back)) == json);
    // Every other declared key is refused, naming what the env reads.
    for (const std::string& key : every) {
      if (set_of(keys).count(key)) continue;
      INFO(key);
      nlohmann::json bad = {{"name", e.name}};
      // A valid value of the key, from an env that reads it.
      for (const EnvEntry& other : env_registry())
        if (env_reads(other, key)) bad[key] = to_json(default_env_config(other.name))[key];
      CHECK_THAT(error_of([&] {
                   ConfigReader r = reader_of(bad);
                   read_env_config(r);
                 }),
                 Contains("env." + key + ": has no effect on " + e.name + " (it reads: name, "));
    }
  }
}

TEST_CASE("an env's option groups are typed and travel with its config", "[config][envs]") {
  EnvConfig button = default_env_config("jaka_button");
  CHECK(button.find<ObstacleOptions>() == nullptr);
  CHECK_THAT(error_of([&] { (void)button.get<ObstacleOptions>(); }), Contains("env jaka_button"));
  button.get<ReachOptions>().action_step = 0.02;
  const EnvConfig copy = button;  // deep copy
  button.get<ReachOptions>().action_step = 0.03;
  CHECK(copy.get<ReachOptions>().action_step == 0.02);
  CHECK(to_json(copy)["action_step"] == 0.02);
  // A config built in code without its groups gets the env's defaults for them.
  EnvConfig bare;
  bare.name = "jaka_obstacle";
  const nlohmann::json json = to_json(bare);
  CHECK(json["max_distance"] == 0.9);
  CHECK(json["column_motion"] == "static");
  CHECK(make_env(bare)->spec().env_name == "jaka_obstacle");
  // A group the env does not read is left out, as its keys would be.
  EnvConfig cart = default_env_config("cartpole");
  cart.options.emplace_back(ReachOptions{});
  CHECK(!to_json(cart).contains("action_step"));
  // The typo still gets its suggestion.
  const nlohmann::json typo_json = {{"name", "jaka_button"}, {"action_stp", 0.01}};
  ConfigReader typo = reader_of(typo_json);
  CHECK_THAT(error_of([&] { read_env_config(typo); }), Contains("env.action_stp") && Contains("did you mean"));
}
