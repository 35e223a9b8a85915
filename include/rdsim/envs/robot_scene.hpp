#pragma once
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rdsim/render/scene.hpp"
#include "rdsim/sim/physics_world.hpp"
#include "rdsim/sim/robot_model.hpp"

// What a camera sees of a PhysicsWorld: one render DrawItem per URDF <visual> of its robots and
// static bodies, in the URDF colours. Built once per env; update_poses() then only copies poses
// (no allocation), so rendering a step costs the draw itself.
namespace rdsim {

// Where one item sits: on link `link` of robot `body`, or on static body `body` (link == -1),
// at `offset` in that frame.
struct ScenePart {
  int body = -1;
  int link = -1;
  int item = -1;
  Eigen::Isometry3f offset = Eigen::Isometry3f::Identity();
};

// Segmentation ids (DrawItem::segment, what a segmentation image shows): 0 is the background;
// then, in the order they are added, one id per link of each robot (every link of its URDF, with
// visuals or not, so a robot's ids follow from its URDF alone) and one per static body.
// `segments[id]` names each: "<robot>/<link>" or the static body's model name. Ids above 255 do
// not fit a segmentation image's byte: their items show 255.
struct RobotScene {
  Scene scene;
  std::vector<ScenePart> parts;
  std::vector<std::string> segments{"background"};
};

// The draw item of a URDF visual shape, centred on the shape (pose = its origin in the link).
DrawItem visual_item(const VisualShape& visual);

// Adds every visual of the robot's links, posed from the robot's current link poses.
void add_robot(RobotScene& scene, const Robot& robot);
// Adds every visual of a static body's model (links at their zero pose), placed by
// world.static_pose(body). `model` must be the model the body was created from.
void add_static_body(RobotScene& scene, const PhysicsWorld& world, int body, const RobotModel& model);

class ReachTask;
// Adds the task's robot and every static body (what every camera of a reaching env draws).
void add_task_bodies(RobotScene& scene, const ReachTask& task);

// Writes every part's current world pose into the scene (after steps, resets, moved statics).
void update_poses(RobotScene& scene, const PhysicsWorld& world);

}  // namespace rdsim
