#include "rdsim/remote/codec.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "rdsim/core/error.hpp"

namespace rdsim::remote {
namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& what) { throw Error("bad reply from the server: " + what); }

const json& member(const json& object, const char* key) {
  if (!object.is_object()) bad("expected an object holding \"" + std::string(key) + "\"");
  const auto it = object.find(key);
  if (it == object.end()) bad("missing \"" + std::string(key) + "\"");
  return *it;
}

bool get_bool(const json& object, const char* key) {
  const json& v = member(object, key);
  if (!v.is_boolean()) bad(std::string(key) + ": expected true or false");
  return v.get<bool>();
}

double get_number(const json& object, const char* key) {
  const json& v = member(object, key);
  if (!v.is_number()) bad(std::string(key) + ": expected a number");
  return v.get<double>();
}

long long get_integer(const json& object, const char* key, long long lo, long long hi) {
  const json& v = member(object, key);
  if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
    bad(std::string(key) + ": expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v.get<long long>();
}

std::string get_string(const json& object, const char* key) {
  const json& v = member(object, key);
  if (!v.is_string()) bad(std::string(key) + ": expected a string");
  return v.get<std::string>();
}

const ArrayFrame& array(const Message& m, const std::string& name, DType dtype, std::size_t count) {
  const ArrayFrame* a = m.find(name);
  if (!a) bad("missing array \"" + name + "\"");
  if (a->dtype != dtype || a->count() != count)
    bad("array \"" + name + "\": expected " + to_string(dtype) + " x " + std::to_string(count) + ", got " +
        to_string(a->dtype) + " x " + std::to_string(a->count()));
  return *a;
}

Eigen::VectorXf floats(const Message& m, const std::string& name, std::size_t count) {
  const ArrayFrame& a = array(m, name, DType::Float32, count);
  Eigen::VectorXf v(static_cast<Eigen::Index>(count));
  if (count) std::memcpy(v.data(), a.bytes.data(), count * sizeof(float));
  return v;
}

void put_floats(Message& m, const std::string& name, const Eigen::VectorXf& v) {
  m.arrays.push_back(ArrayFrame::float32(name, v.data(), {static_cast<int>(v.size())}));
}

// spec.observation.parts: [[name, size], ...], unique names whose sizes add up to `count` values.
std::vector<ObservationPart> get_parts(const json& parts, long long count) {
  const char* expected = "spec.observation.parts: expected [[name, size], ...] covering the observation's values once";
  if (!parts.is_array() || static_cast<long long>(parts.size()) > count) bad(expected);
  std::vector<ObservationPart> out;
  std::set<std::string> names;
  long long total = 0;
  for (const json& p : parts) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_string() || !p[1].is_number_integer()) bad(expected);
    const auto name = p[0].get<std::string>();
    const auto size = p[1].get<long long>();
    if (name.empty() || name.size() > 256 || size < 1 || size > count || !names.insert(name).second) bad(expected);
    total += size;
    out.push_back({name, static_cast<int>(size)});
  }
  if (total != count) bad(expected);
  return out;
}

}  // namespace

void put_spec(Message& m, const Spec& spec) {
  const ObservationSpace& o = spec.observation;
  json action = {{"discrete", spec.action.discrete}};
  if (spec.action.discrete) action["n"] = spec.action.n;
  else action["dim"] = spec.action.dim();
  m.header["spec"] = {{"env_name", spec.env_name},
                      {"observation", {{"dtype", o.type == ObsType::UInt8 ? "uint8" : "float32"}, {"shape", o.shape}}},
                      {"action", action},
                      {"max_episode_steps", spec.max_episode_steps},
                      {"control_dt", spec.control_dt}};
  if (o.vector_size > 0) m.header["spec"]["observation"]["vector_size"] = o.vector_size;  // Float32 values beside the image
  if (!o.parts.empty()) {  // what each value is: [[name, size], ...] (ObservationSpace::parts)
    json parts = json::array();
    for (const ObservationPart& p : o.parts) parts.push_back(json::array({p.name, p.size}));
    m.header["spec"]["observation"]["parts"] = std::move(parts);
  }
  if (spec.goal.active())  // a goal env: the observation's slices and its reward (core/goal_layout.hpp)
    m.header["spec"]["goal"] = {{"observation", spec.goal.observation},
                                {"points", spec.goal.points},
                                {"distance_threshold", spec.goal.distance_threshold},
                                {"reward", to_string(spec.goal.reward)}};
  if (o.value_count() > 0) {
    put_floats(m, "observation_low", o.low);
    put_floats(m, "observation_high", o.high);
  }
  if (!spec.action.discrete) {
    put_floats(m, "action_low", spec.action.low);
    put_floats(m, "action_high", spec.action.high);
  }
}

Spec get_spec(const Message& m) {
  const json& s = member(m.header, "spec");
  Spec spec;
  spec.env_name = get_string(s, "env_name");
  const json& o = member(s, "observation");
  const std::string dtype = get_string(o, "dtype");
  if (dtype != "float32" && dtype != "uint8") bad("spec.observation.dtype: expected float32 or uint8");
  spec.observation.type = dtype == "uint8" ? ObsType::UInt8 : ObsType::Float32;
  const json& shape = member(o, "shape");
  if (!shape.is_array() || shape.empty() || shape.size() > 3) bad("spec.observation.shape: expected 1 to 3 sizes");
  long long count = 1;
  for (const json& d : shape) {
    if (!d.is_number_integer() || d.get<long long>() < 1 || d.get<long long>() > 65536)
      bad("spec.observation.shape: expected sizes 1..65536");
    count *= d.get<long long>();
    spec.observation.shape.push_back(d.get<int>());
  }
  if (count > (1LL << 28)) bad("spec.observation.shape: too large");
  if (o.contains("vector_size")) {
    if (shape.size() != 3) bad("spec.observation.vector_size: expected only beside an image (a shape of 3 sizes)");
    spec.observation.vector_size = static_cast<int>(get_integer(o, "vector_size", 1, 65536));
  }
  const ObservationSpace& space = spec.observation;
  if (space.value_count() > 0) {
    spec.observation.low = floats(m, "observation_low", static_cast<std::size_t>(space.value_count()));
    spec.observation.high = floats(m, "observation_high", static_cast<std::size_t>(space.value_count()));
  }
  if (o.contains("parts")) spec.observation.parts = get_parts(member(o, "parts"), space.vector_size > 0 ? space.vector_size : count);
  const json& a = member(s, "action");
  spec.action.discrete = get_bool(a, "discrete");
  if (spec.action.discrete) {
    spec.action.n = static_cast<int>(get_integer(a, "n", 1, 1 << 20));
  } else {
    const auto dim = static_cast<std::size_t>(get_integer(a, "dim", 1, 1024));
    spec.action.low = floats(m, "action_low", dim);
    spec.action.high = floats(m, "action_high", dim);
  }
  spec.max_episode_steps = static_cast<int>(get_integer(s, "max_episode_steps", 0, std::numeric_limits<int>::max()));
  spec.control_dt = get_number(s, "control_dt");
  if (s.contains("goal")) {
    const json& g = member(s, "goal");
    spec.goal.observation = static_cast<int>(get_integer(g, "observation", 0, space.value_count()));
    spec.goal.points = static_cast<int>(get_integer(g, "points", 1, 1024));
    spec.goal.distance_threshold = static_cast<float>(get_number(g, "distance_threshold"));
    const std::optional<GoalReward> reward = goal_reward_from_string(get_string(g, "reward"));
    if (!reward) bad("spec.goal.reward: expected sparse, partial or dense");
    spec.goal.reward = *reward;
    if (spec.goal.size() != space.value_count() || !(spec.goal.distance_threshold > 0.0f))
      bad("spec.goal: expected float32 values of observation + 6 x points and a threshold > 0");
  }
  return spec;
}

void put_robot_info(Message& m, const RobotInfo* info) {
  if (!info) {
    m.header["robot"] = nullptr;
    return;
  }
  json joints = json::array(), cameras = json::array();
  const auto n = static_cast<Eigen::Index>(info->joints.size());
  Eigen::VectorXf lower(n), upper(n), speed(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const JointInfo& j = info->joints[static_cast<std::size_t>(i)];
    joints.push_back({{"name", j.name}, {"kind", to_string(j.kind)}});
    lower[i] = j.lower;
    upper[i] = j.upper;
    speed[i] = j.max_velocity;
  }
  for (const CameraInfo& c : info->cameras) cameras.push_back({{"name", c.name}, {"link", c.link}, {"fov_deg", c.fov_deg}});
  m.header["robot"] = {{"robot", info->robot}, {"effector_link", info->effector_link}, {"joints", joints}, {"cameras", cameras}};
  put_floats(m, "joint_lower", lower);
  put_floats(m, "joint_upper", upper);
  put_floats(m, "joint_max_velocity", speed);
  put_floats(m, "workspace_min", info->workspace.min());
  put_floats(m, "workspace_max", info->workspace.max());
}

std::optional<RobotInfo> get_robot_info(const Message& m) {
  const json& r = member(m.header, "robot");
  if (r.is_null()) return std::nullopt;
  RobotInfo info;
  info.robot = get_string(r, "robot");
  info.effector_link = get_string(r, "effector_link");
  const json& joints = member(r, "joints");
  if (!joints.is_array() || joints.size() > 4096) bad("robot.joints: expected a list");
  const std::size_t n = joints.size();
  const Eigen::VectorXf lower = floats(m, "joint_lower", n), upper = floats(m, "joint_upper", n),
                        speed = floats(m, "joint_max_velocity", n);
  for (std::size_t i = 0; i < n; ++i) {
    JointInfo j;
    j.name = get_string(joints[i], "name");
    const std::string kind = get_string(joints[i], "kind");
    j.kind = kind == "prismatic" ? JointKind::Prismatic : kind == "continuous" ? JointKind::Continuous : JointKind::Revolute;
    const auto k = static_cast<Eigen::Index>(i);
    j.lower = lower[k];
    j.upper = upper[k];
    j.max_velocity = speed[k];
    info.joints.push_back(j);
  }
  const json& cameras = member(r, "cameras");
  if (!cameras.is_array() || cameras.size() > 64) bad("robot.cameras: expected a list");
  for (const json& c : cameras)
    info.cameras.push_back({get_string(c, "name"), get_string(c, "link"), static_cast<float>(get_number(c, "fov_deg"))});
  const Eigen::Vector3f lo = floats(m, "workspace_min", 3), hi = floats(m, "workspace_max", 3);
  info.workspace = Eigen::AlignedBox3f(lo, hi);
  return info;
}

// "observation": the image (UInt8 bytes, or a Float32 image's values) or the vector;
// "observation_vector": the Float32 values beside an image (ObservationSpace::vector_size).
void put_observation(Message& m, const Spec& spec, const Observation& o) {
  const ObservationSpace& space = spec.observation;
  if (space.type == ObsType::UInt8)
    m.arrays.push_back(ArrayFrame::uint8("observation", o.pixels.data(), space.shape));
  else
    m.arrays.push_back(ArrayFrame::float32("observation", o.values.data(), {space.size()}));
  if (space.vector_size > 0)
    m.arrays.push_back(ArrayFrame::float32("observation_vector", o.values.data() + (space.value_count() - space.vector_size),
                                           {space.vector_size}));
}

Observation get_observation(const Message& m, const Spec& spec) {
  const ObservationSpace& space = spec.observation;
  const auto count = static_cast<std::size_t>(space.size());
  Observation o;
  if (space.type == ObsType::UInt8) {
    const ArrayFrame& a = array(m, "observation", DType::UInt8, count);
    o.pixels.assign(a.bytes.begin(), a.bytes.end());
    if (space.vector_size > 0) o.values = floats(m, "observation_vector", static_cast<std::size_t>(space.vector_size));
  } else {
    o.values = floats(m, "observation", count);
    if (space.vector_size > 0) {
      o.values.conservativeResize(space.value_count());
      o.values.tail(space.vector_size) = floats(m, "observation_vector", static_cast<std::size_t>(space.vector_size));
    }
  }
  return o;
}

void put_step_result(Message& m, const Spec& spec, const StepResult& r) {
  m.header["reward"] = r.reward;
  m.header["terminated"] = r.terminated;
  m.header["truncated"] = r.truncated;
  m.header["info"] = {{"success", r.info.success},
                      {"collision", r.info.collision},
                      {"out_of_bounds", r.info.out_of_bounds},
                      {"distance", r.info.distance}};
  put_observation(m, spec, r.observation);
}

StepResult get_step_result(const Message& m, const Spec& spec) {
  StepResult r;
  r.reward = static_cast<float>(get_number(m.header, "reward"));
  r.terminated = get_bool(m.header, "terminated");
  r.truncated = get_bool(m.header, "truncated");
  const json& info = member(m.header, "info");
  r.info.success = get_bool(info, "success");
  r.info.collision = get_bool(info, "collision");
  r.info.out_of_bounds = get_bool(info, "out_of_bounds");
  r.info.distance = static_cast<float>(get_number(info, "distance"));
  r.observation = get_observation(m, spec);
  return r;
}

void put_robot_state(Message& m, const RobotSnapshot& s) {
  m.header["steps"] = s.steps;
  put_floats(m, "joint_positions", s.joint_positions);
  put_floats(m, "joint_velocities", s.joint_velocities);
  put_floats(m, "joint_targets", s.joint_targets);
  put_floats(m, "effector_position", s.effector_position);
  put_floats(m, "effector_orientation", s.effector_orientation.coeffs());  // x, y, z, w
  put_floats(m, "target", s.target);
  m.header["bodies"] = s.bodies.size();
  Eigen::VectorXf poses(7 * static_cast<Eigen::Index>(s.bodies.size()));  // x, y, z, qx, qy, qz, qw each
  for (size_t b = 0; b < s.bodies.size(); ++b) {
    poses.segment<3>(7 * static_cast<Eigen::Index>(b)) = s.bodies[b].position;
    poses.segment<4>(7 * static_cast<Eigen::Index>(b) + 3) = s.bodies[b].orientation.coeffs();
  }
  put_floats(m, "body_poses", poses);
}

RobotSnapshot get_robot_state(const Message& m, int joints) {
  const auto n = static_cast<std::size_t>(joints);
  RobotSnapshot s;
  s.steps = static_cast<int>(get_integer(m.header, "steps", 0, std::numeric_limits<int>::max()));
  s.joint_positions = floats(m, "joint_positions", n);
  s.joint_velocities = floats(m, "joint_velocities", n);
  s.joint_targets = floats(m, "joint_targets", n);
  s.effector_position = floats(m, "effector_position", 3);
  s.effector_orientation.coeffs() = floats(m, "effector_orientation", 4);
  s.target = floats(m, "target", 3);
  if (m.header.contains("bodies")) {  // servers before body poses sent none
    const auto bodies = static_cast<std::size_t>(get_integer(m.header, "bodies", 0, 1024));
    const Eigen::VectorXf poses = floats(m, "body_poses", 7 * bodies);
    for (std::size_t b = 0; b < bodies; ++b) {
      const auto at = static_cast<Eigen::Index>(7 * b);
      BodyPose pose{poses.segment<3>(at), Eigen::Quaternionf(poses[at + 6], poses[at + 3], poses[at + 4], poses[at + 5])};
      if (!pose.position.allFinite() || !(std::abs(pose.orientation.norm() - 1.0f) < 1e-3f)) bad("body_poses: expected finite points and unit quaternions");
      s.bodies.push_back(pose);
    }
  }
  return s;
}

void put_image(Message& m, const std::string& camera, const Image& image) {
  m.arrays.push_back(ArrayFrame::uint8(camera, image.rgb.data(), {image.height, image.width, 3}));
}

Image get_image(const Message& m, const std::string& camera, int width, int height) {
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3;
  const ArrayFrame& a = array(m, camera, DType::UInt8, count);
  if (a.shape != std::vector<int>{height, width, 3}) bad("array \"" + camera + "\": expected shape [height, width, 3]");
  Image image;
  image.width = width;
  image.height = height;
  image.rgb.assign(a.bytes.begin(), a.bytes.end());
  return image;
}

}  // namespace rdsim::remote
