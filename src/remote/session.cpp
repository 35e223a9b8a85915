#include "rdsim/remote/session.hpp"

#include <algorithm>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/env_caches.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/arm_options.hpp"
#include "rdsim/envs/pixel_view.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/codec.hpp"
#include "rdsim/remote/protocol.hpp"

namespace rdsim::remote {
namespace {

EnvConfig read_hello_env(const nlohmann::json& env) {
  ConfigReader reader(env, "hello", "env");
  EnvConfig c = read_env_config(reader);
  if (const auto* reach = c.find<ReachOptions>(); reach && !reach->urdf_root.empty())
    reader.fail("urdf_root", "not accepted over the link: the server uses its own assets");
  if (const auto* arm = c.find<ArmOptions>(); arm && (!arm->urdf.empty() || !arm->package_paths.empty()))
    reader.fail(arm->urdf.empty() ? "package_paths" : "urdf",
                "not accepted over the link: the server loads only its own robots");
  if (c.render_mode != RenderMode::None)
    reader.fail("render_mode", "not available over the link: ask for camera images with the cameras request");
  if (c.observation == ObservationMode::RawPixels) {
    const ImageChannels channels(c.image_channels);
    const std::size_t per_pixel = channels.uint8() ? 3 : sizeof(float) * static_cast<std::size_t>(channels.count());
    const std::size_t bytes = static_cast<std::size_t>(c.image_width) * static_cast<std::size_t>(c.image_height) *
                              per_pixel * (c.multi_view ? 2 : 1);
    if (bytes > max_observation_bytes)
      reader.fail("image_width", "an observation of " + std::to_string(c.image_width) + "x" + std::to_string(c.image_height) +
                                     " pixels is larger than this server allows (" +
                                     std::to_string(max_observation_bytes >> 20) + " MiB)");
  }
  return c;
}

}  // namespace

Message reply_to(long long id, RequestKind kind) {
  Message m;
  m.header["id"] = id;
  m.header["reply"] = to_string(kind);
  return m;
}

Message error_reply(const nlohmann::json& id, const std::string& what) {
  Message m;
  m.header["id"] = id;
  m.header["error"] = what;
  return m;
}

Session::Session(const Request& hello) : config_(read_hello_env(hello.env)) {
  env_ = make_env(config_);
  control_ = dynamic_cast<RobotControl*>(env_.get());
}

Session::~Session() = default;

Message Session::hello_reply(long long id) const {
  Message m = reply_to(id, RequestKind::Hello);
  m.header["protocol"] = protocol_version;
  m.header["server"] = std::string("rdsim ") + RDSIM_VERSION;
  m.header["env"] = to_json(config_);
  put_spec(m, env_->spec());
  put_robot_info(m, control_ ? &control_->robot_info() : nullptr);
  return m;
}

RobotControl& Session::robot(const Request& q) {
  if (!control_)
    throw Error(std::string(to_string(q.kind)) + ": " + config_.name +
                " has no robot to control (position, joints, cameras and state need a robot env)");
  return *control_;
}

Message Session::step_reply(const Request& q, const StepResult& r, bool with_state) {
  ++steps_;
  Message m = reply_to(q.id, q.kind);
  put_step_result(m, env_->spec(), r);
  if (with_state) {
    const RobotSnapshot s = control_->robot_state();
    m.arrays.push_back(ArrayFrame::float32("joint_positions", s.joint_positions.data(),
                                           {static_cast<int>(s.joint_positions.size())}));
    m.arrays.push_back(ArrayFrame::float32("effector_position", s.effector_position.data(), {3}));
  }
  return m;
}

Message Session::handle(const Request& q) {
  const Spec& spec = env_->spec();
  const std::string name = to_string(q.kind);
  const bool steps = q.kind == RequestKind::Step || q.kind == RequestKind::Position || q.kind == RequestKind::Joints;
  if (steps && !started_) throw Error(name + ": the episode has not started: send reset first");
  switch (q.kind) {
    case RequestKind::Reset: {
      Message m = reply_to(q.id, q.kind);
      put_observation(m, spec, env_->reset(q.seed));
      started_ = true;
      return m;
    }
    case RequestKind::Step: {
      Action action;
      if (spec.action.discrete) {
        if (!q.action_index || *q.action_index < 0 || *q.action_index >= spec.action.n)
          throw Error("step: action: expected an integer in 0.." + std::to_string(spec.action.n - 1) + " (Discrete(" +
                      std::to_string(spec.action.n) + "))");
        action = Action::discrete(*q.action_index);
      } else {
        if (q.action_index || static_cast<int>(q.action_values.size()) != spec.action.dim())
          throw Error("step: action: expected a list of " + std::to_string(spec.action.dim()) + " numbers (Box(" +
                      std::to_string(spec.action.dim()) + "))");
        action = Action::continuous(Eigen::Map<const Eigen::VectorXf>(q.action_values.data(), spec.action.dim()));
      }
      return step_reply(q, env_->step(action), false);
    }
    case RequestKind::Position: return step_reply(q, robot(q).move_effector(q.position), true);
    case RequestKind::Joints: {
      RobotControl& r = robot(q);
      const Eigen::Map<const Eigen::VectorXf> targets(q.joints.data(), static_cast<Eigen::Index>(q.joints.size()));
      return step_reply(q, r.set_joint_targets(targets), true);
    }
    case RequestKind::State: {
      Message m = reply_to(q.id, q.kind);
      put_robot_state(m, robot(q).robot_state());
      return m;
    }
    case RequestKind::Cameras: {
      RobotControl& r = robot(q);
      const std::vector<CameraInfo>& cameras = r.robot_info().cameras;
      std::vector<int> chosen;
      if (q.cameras.empty())
        for (int i = 0; i < static_cast<int>(cameras.size()); ++i) chosen.push_back(i);
      for (const std::string& wanted : q.cameras) {
        int index = -1;
        std::string known;
        for (int i = 0; i < static_cast<int>(cameras.size()); ++i) {
          if (cameras[static_cast<std::size_t>(i)].name == wanted) index = i;
          known += (known.empty() ? "" : ", ") + cameras[static_cast<std::size_t>(i)].name;
        }
        if (index < 0) throw Error("cameras: no camera \"" + wanted + "\" (this robot has: " + known + ")");
        if (std::find(chosen.begin(), chosen.end(), index) != chosen.end())
          throw Error("cameras: \"" + wanted + "\" is named twice");
        chosen.push_back(index);
      }
      Message m = reply_to(q.id, q.kind);
      Image image;
      for (int i : chosen) {
        r.camera_image(i, q.width, q.height, image);
        put_image(m, cameras[static_cast<std::size_t>(i)].name, image);
      }
      return m;
    }
    case RequestKind::Hello: throw Error("hello: this connection already has a session: send close first");
    case RequestKind::DropCaches:
      if (auto* caches = dynamic_cast<EnvCaches*>(env_.get())) caches->drop_caches();
      return reply_to(q.id, q.kind);
    case RequestKind::Close: return reply_to(q.id, q.kind);
  }
  throw Error("unknown request");
}

}  // namespace rdsim::remote
