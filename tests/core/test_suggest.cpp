// "Did you mean": edit distance and the closest valid name, shared by config keys, env names and commands.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "../error_of.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/suggest.hpp"

using Catch::Matchers::Contains;
using rdsim::test::error_of;

TEST_CASE("edit distance counts insertions, deletions and substitutions", "[suggest]") {
  CHECK(rdsim::edit_distance("", "") == 0);
  CHECK(rdsim::edit_distance("abc", "") == 3);
  CHECK(rdsim::edit_distance("kitten", "sitting") == 3);
  CHECK(rdsim::edit_distance("learnig_rate", "learning_rate") == 1);
  CHECK(rdsim::edit_distance("tran", "train") == rdsim::edit_distance("train", "tran"));
}

TEST_CASE("the closest name is offered for typos only", "[suggest]") {
  const std::vector<std::string> envs = {"cartpole", "pendulum", "jaka_button", "jaka_obstacle", "inmoov_tomato"};
  CHECK(rdsim::closest_name("jaka_buton", envs) == "jaka_button");
  CHECK(rdsim::closest_name("CartPole", envs) == "cartpole");  // case ignored
  CHECK(rdsim::closest_name("inmov_tomatoe", envs) == "inmoov_tomato");
  CHECK(rdsim::closest_name("jaka", envs) == "jaka_button");  // a prefix: the first command it begins
  CHECK(rdsim::closest_name("pong", envs).empty());           // nothing close: no guess
  CHECK(rdsim::closest_name("", envs).empty());
  CHECK(rdsim::closest_name("ab", {"cd", "env"}).empty());     // short words need a close match
  CHECK(rdsim::did_you_mean("cartpol", envs) == " (did you mean \"cartpole\"?)");
  CHECK(rdsim::did_you_mean("hopper", envs).empty());
}

TEST_CASE("a mistyped config key or choice names the one meant", "[suggest][config]") {
  const auto j = nlohmann::json::parse(R"({"learnig_rate": 0.1, "gamma": 0.9})");
  CHECK_THAT(error_of([&] {
               rdsim::ConfigReader r(j, "cfg.json", "ppo");
               double lr = 0, gamma = 0;
               r.read("learning_rate", lr, 0.0, 1.0);
               r.read("gamma", gamma, 0.0, 1.0);
               r.finish();
             }),
             Contains("cfg.json: ppo.learnig_rate: unknown key (did you mean \"learning_rate\"?) (known keys here: gamma, "
                      "learning_rate)"));
  const auto k = nlohmann::json::parse(R"({"algorithm": "pp0"})");
  CHECK_THAT(error_of([&] {
               rdsim::ConfigReader r(k, "cfg.json");
               std::string algorithm = "ppo";
               r.read_choice("algorithm", algorithm, {"ppo", "sac", "dqn"});
             }),
             Contains("algorithm: expected one of \"ppo\", \"sac\", \"dqn\", got \"pp0\" (did you mean \"ppo\"?)"));
}
