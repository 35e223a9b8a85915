#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/urdf_loader.hpp"
#include "sim_test_assets.hpp"

using namespace rdsim;

namespace {

constexpr double kDeg = M_PI / 180.0;

// A scratch folder for hand-written URDFs, removed at the end of the test case.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("rdsim_urdf_test_" + std::to_string(std::hash<std::string>{}(Catch::getResultCapture().getCurrentTestName())));
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string file = (path / name).string();
    std::ofstream(file) << text;
    return file;
  }
};

std::string urdf_link(const std::string& name, const std::string& geometry = "<box size=\"0.1 0.1 0.1\"/>") {
  return "<link name=\"" + name + "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" "
         "iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial><collision><geometry>" + geometry +
         "</geometry></collision></link>";
}

std::string urdf_joint(const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& type = "revolute") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" "
         "velocity=\"1\"/></joint>";
}

std::string robot(const std::string& body) { return "<?xml version=\"1.0\"?><robot name=\"t\">" + body + "</robot>"; }

// The error must name the file and mention `what`.
void require_error(const std::string& file, const std::string& what) {
  try {
    load_urdf(file);
    FAIL("no rdsim::Error for " << file);
  } catch (const Error& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message.find(file) != std::string::npos);
    CHECK(message.find(what) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("The Jaka Zu 7 asset loads with its joints, limits and masses", "[urdf]") {
  const RobotModel m = load_urdf(test_asset("jaka/jaka_zu7.urdf"));
  CHECK(m.name == "jaka_zu7");
  REQUIRE(m.links.size() == 8);
  REQUIRE(m.joints.size() == 7);
  CHECK(m.movable_joint_count() == 6);
  const char* names[] = {"joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6", "flange_fixed"};
  for (int i = 0; i < 7; ++i) {
    CHECK(m.joints[static_cast<size_t>(i)].name == names[i]);
    CHECK(m.joints[static_cast<size_t>(i)].child_link == i + 1);  // tree order
  }
  CHECK(m.links[0].name == "base_link");
  CHECK(m.links[7].name == "flange_link");
  CHECK(m.joints[6].type == JointType::Fixed);

  // Zu series limits (degrees).
  const double lower[] = {-360, -85, -175, -85, -360, -360}, upper[] = {360, 265, 175, 265, 360, 360};
  for (int i = 0; i < 6; ++i) {
    const Joint& j = m.joints[static_cast<size_t>(i)];
    CHECK(j.type == JointType::Revolute);
    CHECK(j.lower == Approx(lower[i] * kDeg).margin(1e-5));
    CHECK(j.upper == Approx(upper[i] * kDeg).margin(1e-5));
    CHECK(j.velocity == Approx(M_PI).margin(1e-3));  // 180 deg/s
    CHECK(j.effort > 0.0);
  }
  CHECK(m.total_mass() == Approx(21.65));
  CHECK(m.links[3].inertial.mass == Approx(3.2));  // forearm
  for (const Link& l : m.links) CHECK_FALSE(l.collisions.empty());

  // The published kinematic lengths are where the joints are.
  CHECK(m.joints[0].origin.translation().z() == Approx(0.12));
  CHECK(m.joints[2].origin.translation().x() == Approx(0.36));
  CHECK(m.joints[3].origin.translation().x() == Approx(0.3035));
  CHECK(m.joints[4].origin.translation().y() == Approx(0.114));
  CHECK(m.joints[5].origin.translation().z() == Approx(-0.110));
  CHECK(m.joints[6].origin.translation().y() == Approx(0.107));
}

TEST_CASE("Scene objects load", "[urdf]") {
  const RobotModel table = load_urdf(test_asset("objects/table.urdf"));
  REQUIRE(table.links.size() == 1);
  REQUIRE(table.links[0].collisions.size() == 1);
  CHECK(table.links[0].collisions[0].type == ShapeType::Box);
  CHECK(table.links[0].visuals.size() == 5);
  const RobotModel button = load_urdf(test_asset("objects/button.urdf"));
  REQUIRE(button.links[0].collisions.size() == 1);
  CHECK(button.links[0].collisions[0].type == ShapeType::Cylinder);
  CHECK(button.links[0].visuals[1].rgba.x() > 0.8f);  // the red cap
  const RobotModel floor = load_urdf(test_asset("objects/floor.urdf"));
  CHECK(floor.links[0].collisions[0].size.x() == Approx(20.0));
}

TEST_CASE("Joints keep the file's order, not urdfdom's alphabetical one", "[urdf]") {
  TempDir dir;
  const std::string file = dir.write(
      "order.urdf", robot(urdf_link("root") + urdf_link("b") + urdf_link("a") + urdf_joint("zeta", "root", "b") + urdf_joint("alpha", "b", "a")));
  const RobotModel m = load_urdf(file);
  REQUIRE(m.joints.size() == 2);
  CHECK(m.joints[0].name == "zeta");
  CHECK(m.joints[1].name == "alpha");
  CHECK(m.links[1].name == "b");
  CHECK(m.links[2].name == "a");
  CHECK(m.source == file);
}

TEST_CASE("Bad URDFs are rdsim::Errors naming the file", "[urdf]") {
  TempDir dir;
  SECTION("missing file") { require_error((dir.path / "nope.urdf").string(), "cannot open"); }
  SECTION("malformed XML") { require_error(dir.write("bad.urdf", "<robot name=\"x\"><link name=\"a\">"), "not a valid URDF"); }
  SECTION("not a robot") { require_error(dir.write("empty.urdf", "<?xml version=\"1.0\"?><thing/>"), "not a valid URDF"); }
  SECTION("a mesh that is not there") {
    require_error(dir.write("mesh.urdf", robot(urdf_link("a", "<mesh filename=\"arm.stl\"/>"))),
                  "link \"a\": mesh \"arm.stl\": file not found (searched: ");
  }
  SECTION("floating joint") {
    require_error(dir.write("float.urdf", robot(urdf_link("a") + urdf_link("b") + urdf_joint("j", "a", "b", "floating"))), "floating");
  }
  SECTION("a printf directive, which urdfdom 3 would expand in its error message") {
    // The fuzzer's finding: urdfdom formatted "%n" from an attribute value and wrote through it.
    std::string text = robot(urdf_link("a"));
    text.insert(text.find("<link"), "<!-- 100% ours -->\n");
    CHECK_NOTHROW(rdsim::load_urdf(dir.write("comment.urdf", text)));
    text.insert(text.find("<link"), "<link name=\"%n%n%s%p\"><origin xyz=\"%n %n %n\"/></link>\n");
    require_error(dir.write("percent.urdf", text), "line 2: not a valid URDF for rdsim: '%' outside a comment");
  }
  SECTION("a file ending inside a UTF-8 character, past whose end TinyXML 2.6 used to read") {
    // The fuzzer's finding: a lead byte announcing 2 or 4 bytes made TinyXML step over the text's end.
    require_error(dir.write("utf8.urdf", robot(urdf_link("a")).substr(0, 60) + "s{\x9f]\x92\xcej\xf4\n"), "not a valid URDF");
    require_error(dir.write("utf8_tag.urdf", robot(urdf_link("a")).substr(0, 60) + "<\xde\xde m\xde"), "not a valid URDF");
  }
  SECTION("two roots") {
    require_error(dir.write("roots.urdf", robot(urdf_link("a") + urdf_link("b"))), "not a valid URDF");
  }
  SECTION("a link with two parents") {
    require_error(dir.write("parents.urdf", robot(urdf_link("a") + urdf_link("b") + urdf_link("c") + urdf_joint("j1", "a", "b") +
                                                  urdf_joint("j2", "a", "c") + urdf_joint("j3", "b", "c"))),
                  "two parent joints");
  }
  SECTION("zero effort") {
    std::string text = robot(urdf_link("a") + urdf_link("b") + urdf_joint("j", "a", "b"));
    text.replace(text.find("effort=\"10\""), 11, "effort=\"0\"");
    require_error(dir.write("effort.urdf", text), "effort");
  }
}
