// Mesh files (STL, OBJ, DAE through Assimp): the hand-made fixtures of tests/sim/meshes, whose
// every number is known, and the process-wide cache.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "../error_of.hpp"
#include "mesh_test_util.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/sim/mesh_file.hpp"
#include "../scratch_dir.hpp"

using namespace rdsim;
using Catch::Matchers::Contains;

namespace {

struct Bounds {
  Eigen::Vector3f lo, hi;
};

Bounds bounds(const TriangleMesh& m) {
  Bounds b{Eigen::Vector3f::Constant(1e30f), Eigen::Vector3f::Constant(-1e30f)};
  for (const Eigen::Vector3f& p : m.positions) {
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

bool near(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float tol = 1e-6f) { return (a - b).cwiseAbs().maxCoeff() <= tol; }

}  // namespace

TEST_CASE("mesh file: the cube in STL and OBJ reads as written, OBJ with its .mtl colour", "[mesh]") {
  for (const char* name : {"cube.stl", "cube.obj"}) {
    INFO(name);
    const TriangleMesh m = read_mesh_file(mesh_fixture(name), Eigen::Vector3d::Ones());
    CHECK(m.triangle_count() == 12);
    CHECK(m.positions.size() == 24);  // 4 corners per face: the faces meet at 90 degrees, so normals split
    CHECK(m.normals.size() == m.positions.size());
    const Bounds b = bounds(m);
    CHECK(near(b.lo, Eigen::Vector3f(-1, -1, -1)));
    CHECK(near(b.hi, Eigen::Vector3f(1, 1, 1)));
    CHECK(enclosed_volume(m) == Approx(8.0));  // wound outward
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      // Flat faces: each normal is the axis the vertex's face looks along, pointing out.
      const Eigen::Vector3f& n = m.normals[i];
      int axis;
      CHECK(n.cwiseAbs().maxCoeff(&axis) == Approx(1.0f));
      CHECK(n[axis] * m.positions[i][axis] > 0.0f);
    }
    if (std::string(name) == "cube.obj") {
      REQUIRE(m.colors.size() == m.positions.size());
      CHECK(near(m.colors[0], Eigen::Vector3f(0.2f, 0.4f, 0.8f)));
    } else {
      CHECK(m.colors.empty());
    }
  }
}

TEST_CASE("mesh file: scale applies per axis, and a mirroring scale keeps the triangles wound outward", "[mesh]") {
  const TriangleMesh m = read_mesh_file(mesh_fixture("cube.stl"), Eigen::Vector3d(0.05, 0.1, 0.2));
  const Bounds b = bounds(m);
  CHECK(near(b.lo, Eigen::Vector3f(-0.05f, -0.1f, -0.2f)));
  CHECK(near(b.hi, Eigen::Vector3f(0.05f, 0.1f, 0.2f)));
  CHECK(enclosed_volume(m) == Approx(0.008));
  const ConvexHull hull = convex_hull(m);
  CHECK(hull.points.size() == 8);
  CHECK(hull.volume == Approx(0.008));

  const TriangleMesh mirrored = read_mesh_file(mesh_fixture("two_posts.obj"), Eigen::Vector3d(-1, 1, 1));
  CHECK(enclosed_volume(mirrored) == Approx(0.18));
  for (std::size_t i = 0; i < mirrored.positions.size(); ++i)  // the posts' outer faces look outward (|x| grows)
    if (std::abs(std::abs(mirrored.positions[i].x()) - 0.5f) < 1e-6f && std::abs(mirrored.normals[i].x()) > 0.9f)
      CHECK(mirrored.normals[i].x() * mirrored.positions[i].x() > 0.0f);
}

TEST_CASE("mesh file: a concave mesh's convex hull spans the gap", "[mesh]") {
  const TriangleMesh m = read_mesh_file(mesh_fixture("two_posts.obj"), Eigen::Vector3d::Ones());
  CHECK(m.triangle_count() == 24);
  CHECK(enclosed_volume(m) == Approx(0.18));  // two posts of 0.3 x 1 x 0.3 m
  const ConvexHull hull = convex_hull(m);
  CHECK(hull.points.size() == 8);
  CHECK(hull.volume == Approx(0.3));  // the box around both
}

TEST_CASE("mesh file: DAE unit and up axis become metres, z up", "[mesh]") {
  // Both files hold the box [0,1] x [0,2] x [0,3] in their units, green.
  const TriangleMesh zup = read_mesh_file(mesh_fixture("box_zup_cm.dae"), Eigen::Vector3d::Ones());  // Z_UP, cm
  Bounds b = bounds(zup);
  CHECK(near(b.lo, Eigen::Vector3f(0, 0, 0)));
  CHECK(near(b.hi, Eigen::Vector3f(0.01f, 0.02f, 0.03f)));
  REQUIRE(zup.colors.size() == zup.positions.size());
  CHECK(near(zup.colors[0], Eigen::Vector3f(0.1f, 0.8f, 0.2f)));
  CHECK(enclosed_volume(zup) == Approx(6e-6));
  // Y_UP, metres: the file's up (+y) becomes +z, its +z comes towards -y.
  const TriangleMesh yup = read_mesh_file(mesh_fixture("box_yup.dae"), Eigen::Vector3d::Ones());
  b = bounds(yup);
  CHECK(near(b.lo, Eigen::Vector3f(0, -3, 0), 1e-5f));
  CHECK(near(b.hi, Eigen::Vector3f(1, 0, 2), 1e-5f));
  CHECK(enclosed_volume(yup) == Approx(6.0));
}

TEST_CASE("mesh file: missing, foreign, empty, malformed and oversized files are one clear error", "[mesh]") {
  rdsim::test::ScratchDir dir("mesh_errors");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
  };
  const Eigen::Vector3d one = Eigen::Vector3d::Ones();
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(dir / "none.stl", one); }), Contains("none.stl: file not found"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(write("a.ply", "ply\n"), one); }),
             Contains("a.ply: unsupported mesh format \".ply\""));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(write("e.stl", ""), one); }), Contains("e.stl: empty file"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(write("g.dae", "<COLLADA><library_geometries>"), one); }),
             Contains("g.dae: not a readable DAE file"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(write("n.obj", "v 0 0 0\nv 1 0 0\n"), one); }), Contains("n.obj: "));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(write("x.obj", "v 1e30 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n"), one); }),
             Contains("x.obj: a vertex is not finite or lies beyond 1000 m"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(mesh_fixture("cube.stl"), Eigen::Vector3d(1, 0, 1)); }),
             Contains("must be finite and non-zero"));
  // DAE accessors must read inside the arrays they name (Assimp does not check; found by fuzz_mesh).
  const auto dae = [&](const std::string& name, const std::string& array, const std::string& accessor) {
    return write(name, "<?xml version=\"1.0\"?><COLLADA version=\"1.4.1\"><library_geometries><geometry id=\"g\"><mesh>"
                       "<source id=\"p\"><float_array id=\"a\"" + array + ">0 0 0 1 0 0 0 1 0</float_array><technique_common>"
                       "<accessor source=\"#a\"" + accessor + "><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/>"
                       "<param name=\"Z\" type=\"float\"/></accessor></technique_common></source><vertices id=\"v\">"
                       "<input semantic=\"POSITION\" source=\"#p\"/></vertices><triangles count=\"1\"><input semantic=\"VERTEX\" "
                       "source=\"#v\" offset=\"0\"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries>"
                       "<library_visual_scenes><visual_scene id=\"s\"><node id=\"n\"><instance_geometry url=\"#g\"/></node>"
                       "</visual_scene></library_visual_scenes><scene><instance_visual_scene url=\"#s\"/></scene></COLLADA>");
  };
  CHECK(read_mesh_file(dae("ok.dae", " count=\"9\"", " count=\"3\" stride=\"3\""), one).indices.size() == 3);
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(dae("nc.dae", "", " count=\"3\" stride=\"3\""), one); }),
             Contains("nc.dae: not a readable DAE file: an <accessor> reads 9 values of \"#a\", which holds 0"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(dae("far.dae", " count=\"9\"", " count=\"30\" stride=\"3\""), one); }),
             Contains("an <accessor> reads 90 values of \"#a\", which holds 9"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(dae("off.dae", " count=\"9\"", " count=\"3\" stride=\"3\" offset=\"1\""), one); }),
             Contains("an <accessor> reads 10 values"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(dae("hex.dae", " count=\"0x9\"", " count=\"3\""), one); }),
             Contains("<float_array> count \"0x9\" is not a whole number"));
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(dae("two.dae", " count=\"9\" count=\"90\"", " count=\"3\""), one); }),
             Contains("<float_array> has two count attributes"));
  // Over the size limit: refused unread (a sparse file).
  const std::string big = write("big.stl", "solid big\n");
  std::filesystem::resize_file(big, max_mesh_bytes + 1);
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(big, one); }), Contains("big.stl: is 33554433 bytes, more than the 33554432 bytes"));
  // Over the triangle limit: a binary STL of 500,001 (degenerate) triangles, 25 MB.
  std::string stl(80, ' ');
  const std::uint32_t count = max_mesh_triangles + 1;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  const std::string many = write("many.stl", stl);
  std::filesystem::resize_file(many, 84 + 50ull * count);
  CHECK_THAT(rdsim::test::error_of([&] { read_mesh_file(many, one); }), Contains("many.stl: more than 500000 triangles"));
}

TEST_CASE("mesh cache: one copy per file and scale, shared by threads that ask at once", "[mesh]") {
  const std::string file = mesh_fixture("cube.obj");
  const auto a = load_mesh(file, Eigen::Vector3d::Ones());
  CHECK(load_mesh(file, Eigen::Vector3d::Ones()) == a);
  CHECK(load_mesh(file, Eigen::Vector3d::Constant(2)) != a);
  CHECK(load_convex_hull(file, Eigen::Vector3d::Ones()) == load_convex_hull(file, Eigen::Vector3d::Ones()));

  const std::string fresh = mesh_fixture("two_posts.obj");
  std::vector<std::shared_ptr<const TriangleMesh>> got(8);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] { got[i] = load_mesh(fresh, Eigen::Vector3d(0.5, 0.5, 0.5)); });
  for (auto& t : threads) t.join();
  CHECK(std::set<const TriangleMesh*>{got[0].get(), got[7].get(), got[3].get()}.size() == 1);
  for (const auto& g : got) CHECK(g == got[0]);
}
