#pragma once
#include <Eigen/Geometry>
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

struct RobotScene {
  Scene scene;
  std::vector<ScenePart> parts;
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
