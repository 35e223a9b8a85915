#include "rdsim/envs/robot_scene.hpp"

#include <algorithm>

#include "rdsim/envs/reaching/reach_task.hpp"

namespace rdsim {

DrawItem visual_item(const VisualShape& visual) {
  const Shape& s = visual.shape;
  DrawItem item;
  switch (s.type) {
    case ShapeType::Box: item = make_box((0.5 * s.size).cast<float>(), visual.rgba); break;
    case ShapeType::Cylinder:
      item = make_cylinder(static_cast<float>(s.radius), static_cast<float>(s.length), visual.rgba);
      break;
    case ShapeType::Sphere: item = make_sphere(static_cast<float>(s.radius), visual.rgba); break;
    case ShapeType::Mesh: item = make_mesh(s.mesh.mesh, visual.rgba); break;
  }
  item.pose = s.origin.cast<float>();
  return item;
}

namespace {

// The next segmentation id, named `name` (RobotScene::segments), as an image's byte holds it.
std::uint8_t new_segment(RobotScene& scene, const std::string& name) {
  const std::size_t id = scene.segments.size();
  scene.segments.push_back(name);
  return static_cast<std::uint8_t>(std::min<std::size_t>(id, 255));
}

}  // namespace

void add_robot(RobotScene& scene, const Robot& robot) {
  const RobotModel& model = robot.model();
  for (size_t l = 0; l < model.links.size(); ++l) {
    const int link = static_cast<int>(l);
    const std::uint8_t segment = new_segment(scene, model.name + "/" + model.links[l].name);
    for (const VisualShape& v : model.links[l].visuals) {
      DrawItem item = visual_item(v);
      item.segment = segment;
      const Eigen::Isometry3f offset = item.pose;
      item.pose = robot.link_pose(link) * offset;
      scene.parts.push_back({robot.body(), link, scene.scene.add(item), offset});
    }
  }
}

void add_static_body(RobotScene& scene, const PhysicsWorld& world, int body, const RobotModel& model) {
  const std::vector<Eigen::Isometry3d> frames = model.link_poses_at_zero();
  const Eigen::Isometry3f pose = world.static_pose(body);
  const std::uint8_t segment = new_segment(scene, model.name);
  for (size_t l = 0; l < model.links.size(); ++l)
    for (const VisualShape& v : model.links[l].visuals) {
      DrawItem item = visual_item(v);
      item.segment = segment;
      const Eigen::Isometry3f offset = frames[l].cast<float>() * item.pose;
      item.pose = pose * offset;
      scene.parts.push_back({body, -1, scene.scene.add(item), offset});
    }
}

void add_task_bodies(RobotScene& scene, const ReachTask& task) {
  add_robot(scene, task.robot());
  for (size_t i = 0; i < task.spec().statics.size(); ++i) {
    const int index = static_cast<int>(i);
    add_static_body(scene, task.world(), task.static_body(index), task.static_model(index));
  }
}

void update_poses(RobotScene& scene, const PhysicsWorld& world) {
  // Parts of one link are adjacent (added link by link), so each link pose is computed once.
  int last_body = -1, last_link = -2;
  Eigen::Isometry3f frame = Eigen::Isometry3f::Identity();
  for (const ScenePart& p : scene.parts) {
    if (p.body != last_body || p.link != last_link) {
      frame = p.link < 0 ? world.static_pose(p.body) : world.robot(p.body).link_pose(p.link);
      last_body = p.body;
      last_link = p.link;
    }
    scene.scene.items[static_cast<size_t>(p.item)].pose = frame * p.offset;
  }
}

}  // namespace rdsim
