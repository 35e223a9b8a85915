#pragma once
#include <optional>

#include "rdsim/core/env.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/remote/message.hpp"

// The wire form of rdsim's types in protocol messages (docs/protocol.md), both directions, in one
// place: a put_* writes header keys and arrays into a reply, its get_* reads them back on the
// client. Readers check what a broken or hostile server could get wrong (missing keys, wrong
// types, sizes that disagree with the spec) and throw rdsim::Error; numbers travel exactly
// (floats as float32 frames, or as JSON numbers, which hold a float exactly).
namespace rdsim::remote {

// "spec" object + observation_low/high (float32 observations) and action_low/high (Box) arrays.
void put_spec(Message& m, const Spec& spec);
Spec get_spec(const Message& m);

// "robot" object + joint_lower/upper/max_velocity and workspace_min/max arrays; "robot": null
// for an env without RobotControl.
void put_robot_info(Message& m, const RobotInfo* info);
std::optional<RobotInfo> get_robot_info(const Message& m);

// The "observation" array: float32 [n] or uint8 [height, width, channels], as the spec says.
void put_observation(Message& m, const Spec& spec, const Observation& o);
Observation get_observation(const Message& m, const Spec& spec);

// "reward", "terminated", "truncated", "info" {success, collision, out_of_bounds, distance} and
// the observation.
void put_step_result(Message& m, const Spec& spec, const StepResult& r);
StepResult get_step_result(const Message& m, const Spec& spec);

// "steps" + joint_positions/velocities/targets, effector_position, effector_orientation
// (x, y, z, w), target arrays; `joints` is the expected joint count.
void put_robot_state(Message& m, const RobotSnapshot& s);
RobotSnapshot get_robot_state(const Message& m, int joints);

// One uint8 [height, width, 3] array per image, named after its camera.
void put_image(Message& m, const std::string& camera, const Image& image);
Image get_image(const Message& m, const std::string& camera, int width, int height);

}  // namespace rdsim::remote
