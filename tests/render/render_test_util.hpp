#pragma once
// Helpers shared by the render tests: where a world point lands in the image, and pixel access.
#include <cstdint>
#include <vector>

#include "rdsim/render/camera.hpp"
#include "rdsim/render/scene.hpp"

namespace rdsim::test {

// The two cameras of RobotDrlSim's Jaka scenes, as the paper gives them (PyBullet yaw/pitch
// orbits, fov 60): the main camera over the workspace and the second, lower one. The envs'
// cameras are these re-aimed at rdsim's layout (envs/reaching/jaka_button.cpp).
inline OrbitView paper_main_view() {
  return OrbitView{.target = {0.316f, -0.2f, -0.1f}, .distance = 1.6f, .yaw_deg = 155.0f, .pitch_deg = -36.0f};
}
inline OrbitView paper_second_view() {
  return OrbitView{.target = {0.316f, 0.316f, -0.105f}, .distance = 1.05f, .yaw_deg = 32.0f, .pitch_deg = -13.0f};
}

struct Pixel {
  int col = 0, row = 0;  // row 0 = top
};

inline Pixel project(const Camera& camera, const Eigen::Vector3f& world) {
  const Eigen::Vector4f clip =
      projection_matrix(camera) * view_matrix(camera) * world.homogeneous();
  const Eigen::Vector2f ndc = clip.head<2>() / clip.w();
  return {static_cast<int>((ndc.x() + 1.0f) * 0.5f * static_cast<float>(camera.width)),
          static_cast<int>((1.0f - ndc.y()) * 0.5f * static_cast<float>(camera.height))};
}

struct Rgb {
  int r, g, b;
};

inline Rgb at(const std::vector<std::uint8_t>& img, int width, Pixel p) {
  const size_t i = (static_cast<size_t>(p.row) * static_cast<size_t>(width) +
                    static_cast<size_t>(p.col)) * 3;
  return {img[i], img[i + 1], img[i + 2]};
}

// Hue test, not brightness: surfaces turned away from the light keep only the ambient term.
inline bool reddish(Rgb c) { return c.r > 60 && c.g < c.r / 3 && c.b < c.r / 3; }

// A camera on +x looking at the origin, z up: image right is world +y, image up is world +z.
inline Camera side_camera(int width, int height, float distance = 2.0f) {
  Camera c;
  c.eye = {distance, 0.0f, 0.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.up = {0.0f, 0.0f, 1.0f};
  c.fov_deg = 60.0f;
  c.width = width;
  c.height = height;
  return c;
}

inline Eigen::Isometry3f at_position(const Eigen::Vector3f& p) {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = p;
  return pose;
}

// About 20 items laid out like the paper's Jaka workspace: floor, table, a six-link arm with
// joint spheres, a button, a target and a few obstacles.
inline Scene workspace_scene() {
  Scene s;
  const Eigen::Vector4f grey(0.6f, 0.6f, 0.62f, 1), wood(0.55f, 0.4f, 0.25f, 1),
      white(0.92f, 0.92f, 0.92f, 1), blue(0.2f, 0.35f, 0.8f, 1), red(0.9f, 0.1f, 0.1f, 1),
      green(0.1f, 0.7f, 0.2f, 1);
  DrawItem floor = make_plane(0, 0, grey);
  floor.pose = at_position({0, 0, -0.65f});
  s.add(floor);
  DrawItem table = make_box({0.6f, 0.45f, 0.02f}, wood);
  table.pose = at_position({0.4f, 0.0f, -0.12f});
  s.add(table);
  for (float x : {-0.15f, 0.95f})
    for (float y : {-0.4f, 0.4f}) {
      DrawItem leg = make_cylinder(0.025f, 0.5f, wood);
      leg.pose = at_position({x, y, -0.39f});
      s.add(leg);
    }
  DrawItem base = make_cylinder(0.07f, 0.1f, white);
  base.pose = at_position({0, 0, -0.05f});
  s.add(base);
  // Arm links alternate capsules and cylinders at a few angles, joints as spheres.
  Eigen::Vector3f joint(0, 0, 0.0f);
  const Eigen::Vector3f dirs[] = {{0, 0, 1}, {0.5f, 0, 0.3f}, {0.6f, 0.1f, -0.2f},
                                  {0.3f, 0.2f, -0.4f}};
  const float lengths[] = {0.15f, 0.3f, 0.28f, 0.12f};
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f d = dirs[i].normalized();
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
    pose.linear() = Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), d).toRotationMatrix();
    pose.translation() = joint + 0.5f * lengths[i] * d;
    DrawItem link = i % 2 == 0 ? make_cylinder(0.05f, lengths[i], white)
                               : make_capsule(0.045f, lengths[i], white);
    link.pose = pose;
    s.add(link);
    DrawItem knuckle = make_sphere(0.055f, blue);
    knuckle.pose = at_position(joint);
    s.add(knuckle);
    joint += lengths[i] * d;
  }
  DrawItem gripper = make_box({0.02f, 0.04f, 0.03f}, blue);
  gripper.pose = at_position(joint);
  s.add(gripper);
  DrawItem button_base = make_box({0.05f, 0.05f, 0.02f}, grey);
  button_base.pose = at_position({0.45f, 0.2f, -0.08f});
  s.add(button_base);
  DrawItem button = make_cylinder(0.03f, 0.03f, red);
  button.pose = at_position({0.45f, 0.2f, -0.05f});
  s.add(button);
  DrawItem target = make_sphere(0.03f, green);
  target.pose = at_position({0.55f, -0.2f, 0.05f});
  s.add(target);
  DrawItem obstacle = make_box({0.04f, 0.04f, 0.1f}, Eigen::Vector4f(0.8f, 0.7f, 0.1f, 1));
  obstacle.pose = at_position({0.7f, 0.1f, 0.0f});
  s.add(obstacle);
  return s;
}

}  // namespace rdsim::test
