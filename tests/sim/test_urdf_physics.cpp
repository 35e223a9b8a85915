// URDF physics sanity (urdf_loader.hpp): values Bullet cannot simulate are errors naming the
// file, the link or joint and the value, instead of a run that trains on nonsense.
#include <catch2/catch.hpp>

#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/urdf_loader.hpp"
#include "sim_test_assets.hpp"

using namespace rdsim;

namespace {

std::string inertial(const std::string& mass, const std::string& ixx = "0.01", const std::string& iyy = "0.01",
                     const std::string& izz = "0.01", const std::string& ixy = "0") {
  return "<inertial><mass value=\"" + mass + "\"/><inertia ixx=\"" + ixx + "\" ixy=\"" + ixy + "\" ixz=\"0\" iyy=\"" + iyy +
         "\" iyz=\"0\" izz=\"" + izz + "\"/></inertial>";
}

// base --(joint "j", `type`, `limit`)--> arm (carrying `arm_inertial`) --(fixed)--> tip (`tip_inertial`)
std::string robot(const std::string& arm_inertial, const std::string& limit = "lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"",
                  const std::string& type = "revolute", const std::string& tip_inertial = "",
                  const std::string& origin = "xyz=\"0 0 0.1\"") {
  return "<?xml version=\"1.0\"?><robot name=\"t\"><link name=\"base\">" + inertial("5") +
         "</link><link name=\"arm\">" + arm_inertial + "<collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>"
         "</link><link name=\"tip\">" + tip_inertial + "</link>"
         "<joint name=\"j\" type=\"" + type + "\"><parent link=\"base\"/><child link=\"arm\"/><origin " + origin +
         "/><axis xyz=\"0 0 1\"/><limit " + limit + "/></joint>"
         "<joint name=\"weld\" type=\"fixed\"><parent link=\"arm\"/><child link=\"tip\"/></joint></robot>";
}

std::string error_of(const std::string& xml) {
  try {
    parse_urdf(xml, "bot.urdf");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("URDF: a well-formed robot loads, massless fixed decorations are fine", "[urdf][physics]") {
  CHECK(error_of(robot(inertial("1"))).empty());
  CHECK(error_of(robot(inertial("1"), "lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"", "revolute", inertial("0", "0", "0", "0")))
            .empty());
  for (const char* asset : {"jaka/jaka_zu7.urdf", "inmoov/inmoov.urdf", "objects/button.urdf", "objects/column.urdf",
                            "objects/floor.urdf", "objects/table.urdf", "objects/tomato_tree.urdf"}) {
    INFO(asset);
    CHECK_NOTHROW(load_urdf(test_asset(asset)));
  }
}

TEST_CASE("URDF: masses must be finite, and positive on every link of a movable joint", "[urdf][physics]") {
  using Catch::Matchers::Contains;
  // urdfdom itself rejects what is not a number ("nan", "inf"); rdsim passes its reason on.
  CHECK_THAT(error_of(robot(inertial("nan"))), Contains("bot.urdf") && Contains("mass [nan] is not a float") && Contains("Link [arm]"));
  CHECK_THAT(error_of(robot(inertial("inf"))), Contains("mass [inf]") && Contains("Link [arm]"));
  CHECK_THAT(error_of(robot(inertial("-1"))), Contains("link \"arm\"") && Contains("mass -1"));
  CHECK_THAT(error_of(robot(inertial("0"))), Contains("link \"arm\"") && Contains("movable joint needs a mass > 0"));
  CHECK_THAT(error_of(robot("")), Contains("link \"arm\"") && Contains("mass 0"));  // no <inertial> at all
  CHECK_THAT(error_of(robot(inertial("1e9"))), Contains("link \"arm\"") && Contains("out of range"));
}

TEST_CASE("URDF: inertias must be physical", "[urdf][physics]") {
  using Catch::Matchers::Contains;
  CHECK_THAT(error_of(robot(inertial("1", "nan"))), Contains("Link [arm]") && Contains("ixx is not a valid double"));
  CHECK_THAT(error_of(robot(inertial("1", "-0.1"))), Contains("link \"arm\"") && Contains("ixx -0.1"));
  CHECK_THAT(error_of(robot(inertial("1", "0", "0", "0"))), Contains("link \"arm\"") && Contains("not positive definite"));
  CHECK_THAT(error_of(robot(inertial("1", "0.01", "0.01", "0.01", "0.02"))), Contains("not positive definite"));
  CHECK_THAT(error_of(robot(inertial("1", "1", "1", "3"))), Contains("link \"arm\"") && Contains("triangle inequality"));
  CHECK_THAT(error_of(robot(inertial("1", "1e30", "1e30", "1e30"))), Contains("link \"arm\"") && Contains("implausible"));
  // A massive link welded to a moving one needs a real inertia too.
  CHECK_THAT(error_of(robot(inertial("1"), "lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"", "revolute", inertial("2", "0", "0", "0"))),
             Contains("link \"tip\"") && Contains("not positive definite"));
}

TEST_CASE("URDF: joint limits, efforts, speeds and origins must be finite", "[urdf][physics]") {
  using Catch::Matchers::Contains;
  const std::string arm = inertial("1");
  CHECK_THAT(error_of(robot(arm, "lower=\"nan\" upper=\"1\" effort=\"10\" velocity=\"1\"")), Contains("joint [j]") && Contains("lower value (nan)"));
  CHECK_THAT(error_of(robot(arm, "lower=\"-1\" upper=\"inf\" effort=\"10\" velocity=\"1\"")), Contains("joint [j]") && Contains("upper value (inf)"));
  CHECK_THAT(error_of(robot(arm, "lower=\"1\" upper=\"-1\" effort=\"10\" velocity=\"1\"")), Contains("lower <= upper"));
  CHECK_THAT(error_of(robot(arm, "lower=\"-1\" upper=\"1\" effort=\"inf\" velocity=\"1\"")), Contains("effort value (inf)"));
  CHECK_THAT(error_of(robot(arm, "lower=\"-1\" upper=\"1\" effort=\"1e400\" velocity=\"1\"")), Contains("bot.urdf"));
  CHECK_THAT(error_of(robot(arm, "lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"0\"")), Contains("velocity> 0"));
  CHECK_THAT(error_of(robot(arm, "lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"", "revolute", "", "xyz=\"nan 0 0\"")),
             Contains("joint [j]") && Contains("[nan]"));
}
