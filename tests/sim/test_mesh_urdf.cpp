// URDFs with <mesh> geometry: where mesh files are found, what errors say, how meshes collide
// (convex hulls on robot links, triangles on static bodies), and pybullet_data's KUKA iiwa and
// Franka Panda read from the installed pybullet package.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "../error_of.hpp"
#include "../scratch_dir.hpp"
#include "mesh_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/sim/mesh_file.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/urdf_loader.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;
using rdsim::test::error_of;

namespace {

// One link "part" holding `geometry` as its collision and visual.
std::string one_link(const std::string& geometry) {
  return R"(<robot name="r"><link name="part"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>)"
         "<visual><geometry>" + geometry + "</geometry></visual><collision><geometry>" + geometry +
         "</geometry></collision></link></robot>";
}

// A fixed base 1 m up, and under it link "block" on a vertical slide whose actuator is too weak to
// hold it (effort 1 uN: it falls freely), colliding through `geometry`.
std::string dropper(const std::string& geometry, double height = 1.0) {
  return R"(<robot name="dropper"><link name="base"/>
    <joint name="slide" type="prismatic"><parent link="base"/><child link="block"/><axis xyz="0 0 1"/>
      <origin xyz="0 0 )" + std::to_string(height) + R"("/><limit lower="-5" upper="5" effort="1e-6" velocity="100"/></joint>
    <link name="block"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
      <collision><geometry>)" + geometry + "</geometry></collision></link></robot>";
}

// A static floor: a 4 x 4 m box whose top is at z = 0.
RobotModel floor_model() {
  return parse_urdf(R"(<robot name="floor"><link name="floor"><collision><origin xyz="0 0 -0.5"/><geometry><box size="4 4 1"/></geometry></collision></link></robot>)",
                    "floor.urdf");
}

Eigen::Isometry3f at(float x, float y, float z) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translation() = Eigen::Vector3f(x, y, z);
  return t;
}

// Height of the dropper's block (link 1) after falling for `seconds`.
float fall(PhysicsWorld& world, Robot& robot, double seconds) {
  for (int i = 0; i < static_cast<int>(seconds / world.settings().time_step); ++i) world.step();
  return robot.link_pose(1).translation().z();
}

}  // namespace

TEST_CASE("mesh URDF: relative and package:// paths resolve as documented", "[urdf][mesh]") {
  const std::string in_meshes = mesh_fixture("inline.urdf");            // a URDF beside the meshes
  const std::string in_sim = mesh_fixture("../inline.urdf");            // a URDF in tests/sim
  const std::string elsewhere = mesh_fixture("../../inline.urdf");      // a URDF in tests/
  const auto file_of = [](const RobotModel& m) { return std::filesystem::path(m.links[0].collisions[0].mesh.file); };
  const std::filesystem::path cube = std::filesystem::canonical(mesh_fixture("cube.stl"));
  const auto is_cube = [&](const RobotModel& m) { return std::filesystem::equivalent(file_of(m), cube); };

  // Relative: the URDF's folder, then the search path.
  CHECK(is_cube(parse_urdf(one_link(R"(<mesh filename="cube.stl"/>)"), in_meshes)));
  CHECK(is_cube(parse_urdf(one_link(R"(<mesh filename="cube.stl"/>)"), elsewhere, {.search_path = {mesh_fixture("")}})));
  // package://NAME/REST: a search dir holding NAME; the nearest folder above the URDF named NAME;
  // the URDF's folder holding NAME (pybullet's reading).
  CHECK(is_cube(parse_urdf(one_link(R"(<mesh filename="package://meshes/cube.stl"/>)"), elsewhere,
                           {.search_path = {"/nonexistent", mesh_fixture("..")}})));
  CHECK(is_cube(parse_urdf(one_link(R"(<mesh filename="package://sim/meshes/cube.stl"/>)"), in_meshes)));
  CHECK(is_cube(parse_urdf(one_link(R"(<mesh filename="package://meshes/cube.stl"/>)"), in_sim)));
  // Absolute paths and file:// URIs.
  CHECK(is_cube(parse_urdf(one_link("<mesh filename=\"" + cube.string() + "\"/>"), elsewhere)));
  CHECK(is_cube(parse_urdf(one_link("<mesh filename=\"file://" + cube.string() + "\"/>"), elsewhere)));
  // The model keeps the URI as written and the scale.
  const RobotModel m = parse_urdf(one_link(R"(<mesh filename="cube.stl" scale="0.1 0.2 0.3"/>)"), in_meshes);
  const Shape& s = m.links[0].collisions[0];
  CHECK(s.type == ShapeType::Mesh);
  CHECK(s.mesh.uri == "cube.stl");
  CHECK(s.mesh.scale == Eigen::Vector3d(0.1, 0.2, 0.3));
  REQUIRE(s.mesh.hull);
  CHECK(s.mesh.hull->volume == Approx(8 * 0.1 * 0.2 * 0.3));
  CHECK(m.links[0].visuals[0].shape.mesh.mesh == s.mesh.mesh);  // one copy for both elements
  CHECK(!m.links[0].visuals[0].shape.mesh.hull);                 // visuals need no hull
}

TEST_CASE("mesh URDF: a missing or bad mesh is one error naming the URDF, the link and the mesh", "[urdf][mesh]") {
  const std::string urdf = mesh_fixture("robot.urdf");
  const std::string missing = error_of([&] {
    parse_urdf(one_link(R"(<mesh filename="package://arm/meshes/link3.obj"/>)"), urdf, {.search_path = {"/opt/robots"}});
  });
  CHECK_THAT(missing, Contains("robot.urdf: link \"part\": mesh \"package://arm/meshes/link3.obj\": file not found (searched: "
                               "/opt/robots/arm/meshes/link3.obj, "));
  CHECK_THAT(missing, Contains("tests/sim/meshes/arm/meshes/link3.obj)"));
  CHECK(missing.find('\n') == std::string::npos);
  CHECK_THAT(error_of([&] { parse_urdf(one_link(R"(<mesh filename="missing.stl"/>)"), urdf); }),
             Contains("robot.urdf: link \"part\": mesh \"missing.stl\": file not found (searched: "));
  CHECK_THAT(error_of([&] { parse_urdf(one_link(R"(<mesh filename="http://example.com/a.stl"/>)"), urdf); }),
             Contains("mesh \"http://example.com/a.stl\": unsupported URI scheme"));
  CHECK_THAT(error_of([&] { parse_urdf(one_link(R"(<mesh filename="package://cube.stl"/>)"), urdf); }),
             Contains("a package:// URI needs a package name and a file"));
  CHECK_THAT(error_of([&] { parse_urdf(one_link(R"(<mesh filename="cube.mtl"/>)"), urdf); }),
             Contains("robot.urdf: link \"part\": mesh \"cube.mtl\": ") && Contains("cube.mtl: unsupported mesh format \".mtl\""));
  CHECK_THAT(error_of([&] { parse_urdf(one_link(R"(<mesh filename="cube.stl" scale="1 0 1"/>)"), urdf); }),
             Contains("mesh \"cube.stl\": scale (1 0 1) must be finite and non-zero"));
}

TEST_CASE("mesh URDF: a static body collides with the mesh's triangles, a robot link with its convex hull", "[urdf][mesh][physics]") {
  // two_posts.obj: two 0.3 m posts with a 0.4 m gap between them (x in [-0.2, 0.2]).
  const RobotModel posts = parse_urdf(one_link(R"(<mesh filename="two_posts.obj"/>)"), mesh_fixture("posts.urdf"));
  SECTION("static: a 10 cm box falls through the gap to the floor") {
    PhysicsWorld world;
    world.add_static_body(floor_model(), Eigen::Isometry3f::Identity());
    const int body = world.add_static_body(posts, Eigen::Isometry3f::Identity());
    Robot& robot = world.add_robot(parse_urdf(dropper(R"(<box size="0.1 0.1 0.1"/>)"), "dropper.urdf"), Eigen::Isometry3f::Identity());
    CHECK(fall(world, robot, 1.5) == Approx(0.05f).margin(0.006f));  // on the floor, not on the posts' tops (0.35)
    CHECK_FALSE(world.touching({robot.body(), 1}, {body, -1}, 0.01f));
    // Beside the gap it lands on a post's top.
    PhysicsWorld world2;
    world2.add_static_body(floor_model(), Eigen::Isometry3f::Identity());
    const int body2 = world2.add_static_body(posts, at(0.35f, 0, 0));
    Robot& robot2 = world2.add_robot(parse_urdf(dropper(R"(<box size="0.1 0.1 0.1"/>)"), "dropper.urdf"), Eigen::Isometry3f::Identity());
    CHECK(fall(world2, robot2, 1.5) == Approx(0.35f).margin(0.006f));
    CHECK(world2.touching({robot2.body(), 1}, {body2, -1}, 0.01f));
    CHECK(world2.penetration({robot2.body(), 1}, {body2, -1}) < 0.005f);
  }
  SECTION("robot link: the hull rests on a thin rod that the gap would let through") {
    PhysicsWorld world;
    const RobotModel rod = parse_urdf(R"(<robot name="rod"><link name="rod"><collision><geometry><box size="0.05 2 0.05"/></geometry></collision></link></robot>)",
                                      "rod.urdf");
    const int body = world.add_static_body(rod, at(0, 0, 0.5f));
    Robot& robot = world.add_robot(parse_urdf(dropper(R"(<mesh filename="two_posts.obj"/>)"), mesh_fixture("dropper.urdf")),
                                   Eigen::Isometry3f::Identity());
    CHECK(fall(world, robot, 1.5) == Approx(0.525f).margin(0.006f));  // the hull's bottom on the rod's top
    CHECK(world.touching({robot.body(), 1}, {body, -1}, 0.01f));
  }
  SECTION("robot link: a scaled cube mesh rests on the floor at its scaled half height") {
    PhysicsWorld world;
    const int floor = world.add_static_body(floor_model(), Eigen::Isometry3f::Identity());
    Robot& robot = world.add_robot(parse_urdf(dropper(R"(<mesh filename="cube.obj" scale="0.05 0.05 0.08"/>)"), mesh_fixture("dropper.urdf")),
                                   Eigen::Isometry3f::Identity());
    CHECK(fall(world, robot, 1.5) == Approx(0.08f).margin(0.004f));
    CHECK(world.touching({robot.body(), 1}, {floor, -1}, 0.01f));
  }
}

TEST_CASE("mesh URDF: inertia from the shapes follows pybullet's rule for mesh links", "[urdf][mesh][physics]") {
  // pybullet's loadURDF without URDF_USE_INERTIA_FROM_FILE: a box's moments around all the mesh's
  // vertices, grown by 1 mm margins: two a side for an STL, three for an OBJ (pybullet wraps its
  // hulls in one more compound), and the link compound's one (tools/fidelity checks real robots).
  RobotOptions options;
  options.inertia_from_shapes = true;
  const auto moments_of = [&](const std::string& geometry, const std::string& urdf) {
    PhysicsWorld world;
    return world.add_robot(parse_urdf(dropper(geometry), urdf), Eigen::Isometry3f::Identity(), options).link_inertia(1);
  };
  const auto box = [](double x, double y, double z) -> Eigen::Vector3d {  // moments of a 1 kg box (kg m^2)
    return Eigen::Vector3d(y * y + z * z, x * x + z * z, x * x + y * y) / 12.0;
  };
  // cube.stl and cube.obj: a cube of side 2 scaled to 0.1 x 0.2 x 0.3 m.
  const Robot::LinkInertia stl = moments_of(R"(<mesh filename="cube.stl" scale="0.05 0.1 0.15"/>)", mesh_fixture("d.urdf"));
  CHECK(stl.mass == 1.0);
  CHECK(stl.moments.isApprox(box(0.106, 0.206, 0.306), 1e-6));
  const Robot::LinkInertia obj = moments_of(R"(<mesh filename="cube.obj" scale="0.05 0.1 0.15"/>)", mesh_fixture("d.urdf"));
  CHECK(obj.moments.isApprox(box(0.108, 0.208, 0.308), 1e-6));
  // A sphere of 0.1 m radius with 1,200 triangles: its collision hull is reduced to at most
  // max_hull_points vertices, whose box is smaller; the moments still come from every vertex.
  rdsim::test::ScratchDir dir("mesh_inertia");
  {
    std::ofstream out(dir / "ball.obj");
    const int rings = 20, sectors = 30;
    for (int i = 0; i <= rings; ++i)
      for (int j = 0; j < sectors; ++j) {
        const double theta = M_PI * i / rings, phi = 2.0 * M_PI * j / sectors;
        out << "v " << 0.1 * std::sin(theta) * std::cos(phi) << ' ' << 0.1 * std::sin(theta) * std::sin(phi) << ' '
            << 0.1 * std::cos(theta) << '\n';
      }
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < sectors; ++j) {
        const int a = i * sectors + j + 1, b = i * sectors + (j + 1) % sectors + 1;
        out << "f " << a << ' ' << a + sectors << ' ' << b + sectors << "\nf " << a << ' ' << b + sectors << ' ' << b << '\n';
      }
  }
  const RobotModel ball = parse_urdf(dropper(R"(<mesh filename="ball.obj"/>)"), dir / "ball.urdf");
  REQUIRE(ball.links[1].collisions[0].mesh.hull);
  REQUIRE(ball.links[1].collisions[0].mesh.hull->points.size() <= max_hull_points);
  Eigen::AlignedBox3f vertices, hull;
  for (const Eigen::Vector3f& p : ball.links[1].collisions[0].mesh.mesh->positions) vertices.extend(p);
  for (const Eigen::Vector3f& p : ball.links[1].collisions[0].mesh.hull->points) hull.extend(p);
  CHECK(hull.sizes().x() < vertices.sizes().x() - 1e-3f);  // the reduced hull's box is smaller
  const Eigen::Vector3d size = vertices.sizes().cast<double>() + Eigen::Vector3d::Constant(0.008);
  PhysicsWorld world;
  const Robot::LinkInertia moments = world.add_robot(ball, Eigen::Isometry3f::Identity(), options).link_inertia(1);
  CHECK(moments.moments.isApprox(box(size.x(), size.y(), size.z()), 1e-6));
  // Without the option: the URDF's tensor.
  PhysicsWorld plain;
  const Robot& urdf_inertia = plain.add_robot(ball, Eigen::Isometry3f::Identity());
  CHECK(urdf_inertia.link_inertia(1).moments.isApprox(Eigen::Vector3d::Constant(0.01)));
  CHECK_THROWS_WITH(urdf_inertia.link_inertia(2), Contains("link 2 out of range"));
}

TEST_CASE("mesh URDF: pybullet_data's KUKA iiwa loads with its meshes", "[urdf][mesh][pybullet_data]") {
  const std::string data = pybullet_data();
  if (data.empty()) return;
  const RobotModel kuka = load_urdf(data + "/kuka_iiwa/model.urdf");
  CHECK(kuka.name == "lbr_iiwa");
  CHECK(kuka.movable_joint_count() == 7);
  REQUIRE(kuka.links.size() == 8);
  for (int i = 0; i < 8; ++i) CHECK(kuka.links[static_cast<size_t>(i)].name == "lbr_iiwa_link_" + std::to_string(i));
  CHECK(kuka.total_mass() == Approx(17.5));
  for (const Link& link : kuka.links) {
    INFO(link.name);
    REQUIRE(link.collisions.size() == 1);
    CHECK(link.collisions[0].type == ShapeType::Mesh);
    CHECK(link.collisions[0].mesh.file.ends_with(".stl"));
    CHECK(link.collisions[0].mesh.hull->points.size() <= max_hull_points);
    CHECK(link.collisions[0].mesh.hull->volume > 1e-4);  // m^3: a link-sized solid
    REQUIRE(link.visuals.size() == 1);
    CHECK(link.visuals[0].shape.mesh.file.ends_with(".obj"));
    CHECK(link.visuals[0].shape.mesh.mesh->triangle_count() > 100);
  }
  CHECK(kuka.links[3].visuals[0].rgba.head<3>().isApprox(Eigen::Vector3f(1.0f, 0.423529411765f, 0.0392156862745f)));  // "Orange"
}

TEST_CASE("mesh URDF: pybullet_data's Franka Panda loads, holds its pose with motors, falls without them onto the floor",
          "[urdf][mesh][physics][pybullet_data]") {
  const std::string data = pybullet_data();
  if (data.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  const RobotModel panda = load_urdf(data + "/franka_panda/panda.urdf");
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  WARN("Panda loaded in " << ms << " ms (its meshes are cached for the process after the first load)");
  CHECK(panda.name == "panda");
  CHECK(panda.movable_joint_count() == 9);  // 7 arm joints and 2 finger slides
  CHECK(panda.links.size() == 13);
  for (const char* name : {"panda_link0", "panda_link7", "panda_hand", "panda_leftfinger", "panda_rightfinger", "panda_grasptarget"})
    CHECK(panda.link_index(name) >= 0);
  CHECK(panda.total_mass() == Approx(17.96));
  // package://meshes/... resolved pybullet's way, beside the URDF.
  const Shape& c3 = panda.links[static_cast<size_t>(panda.require_link("panda_link3"))].collisions.at(0);
  CHECK(c3.mesh.uri == "package://meshes/collision/link3.obj");
  CHECK(std::filesystem::equivalent(c3.mesh.file, data + "/franka_panda/meshes/collision/link3.obj"));

  PhysicsWorld world;
  const int floor = world.add_static_body(floor_model(), Eigen::Isometry3f::Identity());
  Eigen::VectorXf bent(9);
  bent << 0.0f, 0.6f, 0.0f, -1.6f, 0.0f, 1.8f, 0.8f, 0.02f, 0.02f;
  const int hand = panda.require_link("panda_hand");

  SECTION("held by its motors") {
    Robot& robot = world.add_robot(panda, Eigen::Isometry3f::Identity());
    REQUIRE(robot.dof() == 9);
    robot.reset_joints(bent);
    const Eigen::Vector3f hand_at = robot.link_pose(hand).translation();
    for (int i = 0; i < 480; ++i) world.step();
    CHECK((robot.joint_positions() - bent).cwiseAbs().maxCoeff() < 0.02f);
    CHECK((robot.link_pose(hand).translation() - hand_at).norm() < 0.01f);
    CHECK_FALSE(world.touching({robot.body(), -1}, {floor, -1}, 0.01f));
  }
  SECTION("without motors it falls until a link lies on the floor") {
    RobotModel limp = panda;
    for (Joint& j : limp.joints)
      if (j.movable()) j.effort = 1e-6;  // a motor too weak to matter
    Robot& robot = world.add_robot(limp, Eigen::Isometry3f::Identity());
    robot.reset_joints(bent);
    const float hand_z = robot.link_pose(hand).translation().z();
    bool touched = false;
    float deepest = 0.0f;
    for (int i = 0; i < 3 * 240; ++i) {
      world.step();
      touched |= world.touching({robot.body(), -1}, {floor, -1}, 0.005f);
      deepest = std::max(deepest, world.penetration({robot.body(), -1}, {floor, -1}));
    }
    CHECK(robot.link_pose(hand).translation().z() < hand_z - 0.1f);
    CHECK(touched);
    CHECK(deepest < 0.02f);  // the floor stops it
    for (int l = 0; l < static_cast<int>(limp.links.size()); ++l) CHECK(robot.link_pose(l).translation().z() > -0.02f);
  }
}

TEST_CASE("mesh URDF: envs built on several threads at once share one copy of each mesh", "[urdf][mesh][pybullet_data]") {
  const std::string data = pybullet_data();
  if (data.empty()) return;
  std::vector<RobotModel> models(6);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < models.size(); ++i)
    threads.emplace_back([&, i] { models[i] = load_urdf(data + "/kuka_iiwa/model.urdf"); });
  for (auto& t : threads) t.join();
  for (const RobotModel& m : models) {
    REQUIRE(m.links.size() == 8);
    for (std::size_t l = 0; l < m.links.size(); ++l) {
      CHECK(m.links[l].visuals[0].shape.mesh.mesh == models[0].links[l].visuals[0].shape.mesh.mesh);
      CHECK(m.links[l].collisions[0].mesh.hull == models[0].links[l].collisions[0].mesh.hull);
    }
  }
}
