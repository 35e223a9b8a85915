// Mesh robots in the pixels: pybullet_data's Franka Panda and KUKA iiwa (from the installed
// pybullet package) drawn through RobotScene by the osmesa renderer.
//   ./build/test_envs "[.demo]"   writes docs/robot_panda.png and docs/robot_kuka_iiwa.png (to
//                                 $RDSIM_DOCS_IMAGES or /tmp; the docs' copies went through
//                                 `convert -strip -define png:compression-level=9`)
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "rdsim/envs/robot_scene.hpp"
#include "rdsim/render/png.hpp"
#include "rdsim/render/renderer.hpp"
#include "rdsim/sim/urdf_loader.hpp"

using namespace rdsim;

namespace {

std::string pybullet_data() {
  const std::string dir = RDSIM_PYBULLET_DATA;
  if (dir.empty())
    WARN("skipped: pybullet_data not found (CMake ran `RDSIM_VENV_PYTHON -c \"import pybullet_data\"` and it failed; "
         "run tools/setup.sh or pass -DRDSIM_VENV_PYTHON=<a python with pybullet>)");
  return dir;
}

struct Image {
  int w, h;
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* at(int col, int row) const { return rgb.data() + (static_cast<size_t>(row) * w + col) * 3; }
};

Image render(const Scene& scene, const Camera& cam) {
  auto r = make_renderer("osmesa", cam.width, cam.height);
  Image img{cam.width, cam.height, std::vector<std::uint8_t>(static_cast<size_t>(cam.width * cam.height * 3))};
  r->render(scene, cam, img.rgb.data());
  return img;
}

// The Panda is white and dark grey (its URDF's white times its .mtl colours): grey pixels, none of
// the background's blue.
bool panda_coloured(const std::uint8_t* p) {
  return std::abs(p[0] - p[1]) < 12 && std::abs(p[1] - p[2]) < 12 && p[0] > 15;
}

Eigen::Vector2i project(const Camera& cam, const Eigen::Vector3f& world) {
  const Eigen::Vector4f clip = projection_matrix(cam) * view_matrix(cam) * world.homogeneous();
  const Eigen::Vector2f ndc = clip.head<2>() / clip.w();
  return {static_cast<int>((ndc.x() + 1.0f) * 0.5f * static_cast<float>(cam.width)),
          static_cast<int>((1.0f - ndc.y()) * 0.5f * static_cast<float>(cam.height))};
}

Camera arm_camera() {
  Camera cam;
  cam.eye = {1.5f, 1.1f, 0.9f};
  cam.target = {0.25f, 0.0f, 0.35f};
  cam.up = {0.0f, 0.0f, 1.0f};
  cam.fov_deg = 50.0f;
  cam.width = 128;
  cam.height = 128;
  return cam;
}

}  // namespace

TEST_CASE("mesh robots: the Panda's pixels lie where its links are, in its colours", "[envs][mesh][pybullet_data]") {
  const std::string data = pybullet_data();
  if (data.empty()) return;
  PhysicsWorld world;
  Robot& robot = world.add_robot(load_urdf(data + "/franka_panda/panda.urdf"), Eigen::Isometry3f::Identity());
  Eigen::VectorXf q(9);
  q << 0.3f, 0.5f, 0.0f, -1.8f, 0.0f, 2.0f, 0.8f, 0.03f, 0.03f;
  robot.reset_joints(q);
  RobotScene scene;
  scene.scene.background = {0.15f, 0.35f, 0.75f};
  add_robot(scene, robot);
  const Camera cam = arm_camera();
  const Image img = render(scene.scene, cam);

  // Each link's visual mesh centre (the middle of its vertices) lands on a Panda pixel.
  int links = 0, covered = 0;
  for (const ScenePart& part : scene.parts) {
    const DrawItem& item = scene.scene.items[static_cast<size_t>(part.item)];
    REQUIRE(item.kind == DrawShape::Mesh);
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
    for (const Eigen::Vector3f& p : item.mesh->positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Eigen::Vector2i px = project(cam, item.pose * (0.5f * (lo + hi)));
    if (px.x() < 1 || px.y() < 1 || px.x() >= cam.width - 1 || px.y() >= cam.height - 1) continue;
    ++links;
    bool hit = false;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) hit |= panda_coloured(img.at(px.x() + dc, px.y() + dr));
    covered += hit;
  }
  CHECK(links >= 8);
  CHECK(covered >= links - 1);  // a link's middle may fall in a gap of its own shape

  int bright = 0, dark = 0, robot_pixels = 0;
  for (int row = 0; row < img.h; ++row)
    for (int col = 0; col < img.w; ++col) {
      const std::uint8_t* p = img.at(col, row);
      if (!panda_coloured(p)) continue;
      ++robot_pixels;
      bright += p[0] > 140;
      dark += p[0] < 75;  // the .mtl's dark grey (0.25) parts: joints' caps, the hand
    }
  CHECK(robot_pixels > 128 * 128 / 20);
  CHECK(bright > 100);
  CHECK(dark > 10);

  // Hidden items leave only background: every grey pixel above was the robot's meshes.
  for (DrawItem& item : scene.scene.items) item.rgba[3] = 0.0f;
  const Image empty = render(scene.scene, cam);
  int left = 0;
  for (int row = 0; row < empty.h; ++row)
    for (int col = 0; col < empty.w; ++col) left += panda_coloured(empty.at(col, row));
  CHECK(left == 0);
}

TEST_CASE("mesh robots: the KUKA arm draws in its URDF's blue and orange", "[envs][mesh][pybullet_data]") {
  const std::string data = pybullet_data();
  if (data.empty()) return;
  PhysicsWorld world;
  Robot& robot = world.add_robot(load_urdf(data + "/kuka_iiwa/model.urdf"), Eigen::Isometry3f::Identity());
  Eigen::VectorXf q(7);
  q << 0.0f, 0.6f, 0.0f, -1.2f, 0.0f, 0.8f, 0.0f;
  robot.reset_joints(q);
  RobotScene scene;
  scene.scene.background = {0.9f, 0.9f, 0.9f};
  add_robot(scene, robot);
  const Image img = render(scene.scene, arm_camera());
  int blue = 0, orange = 0;
  for (int row = 0; row < img.h; ++row)
    for (int col = 0; col < img.w; ++col) {
      const std::uint8_t* p = img.at(col, row);
      blue += p[2] > p[0] + 30 && p[2] > p[1];
      orange += p[0] > p[1] + 40 && p[1] > p[2] + 20;
    }
  CHECK(blue > 200);
  CHECK(orange > 50);
}

TEST_CASE("mesh robots: the docs' pictures of the Panda and the KUKA arm", "[.demo]") {
  const std::string data = pybullet_data();
  if (data.empty()) return;
  const char* dir = std::getenv("RDSIM_DOCS_IMAGES");
  const std::string out = dir && *dir ? dir : "/tmp";
  struct Bot {
    const char* urdf;
    const char* png;
    std::vector<float> q;
  };
  for (const Bot& b : {Bot{"/franka_panda/panda.urdf", "/robot_panda.png", {0.3f, 0.4f, 0.0f, -1.9f, 0.0f, 2.2f, 0.8f, 0.03f, 0.03f}},
                       Bot{"/kuka_iiwa/model.urdf", "/robot_kuka_iiwa.png", {0.3f, 0.6f, 0.0f, -1.3f, 0.0f, 0.9f, 0.0f}}}) {
    PhysicsWorld world;
    Robot& robot = world.add_robot(load_urdf(data + b.urdf), Eigen::Isometry3f::Identity());
    robot.reset_joints(Eigen::Map<const Eigen::VectorXf>(b.q.data(), static_cast<Eigen::Index>(b.q.size())));
    RobotScene scene;
    scene.scene.add(make_plane(1.0f, 1.0f, Eigen::Vector4f(0.55f, 0.55f, 0.6f, 1.0f)));  // a floor
    add_robot(scene, robot);
    const Image img = render(scene.scene, make_orbit_camera(OrbitView{.target = {0.25f, 0.0f, 0.4f}, .distance = 1.45f,
                                                                      .yaw_deg = 40.0f, .pitch_deg = -22.0f},
                                                            224, 224));
    write_png(out + b.png, img.w, img.h, 3, img.rgb.data());
  }
}
