#include "rdsim/remote/remote_env.hpp"

#include <nlohmann/json.hpp>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/codec.hpp"
#include "rdsim/remote/protocol.hpp"
#include "remote_link.hpp"

namespace rdsim {
namespace {

remote::Message request(const char* kind) {
  remote::Message m;
  m.header["request"] = kind;
  return m;
}

nlohmann::json float_list(const float* v, Eigen::Index n) {
  nlohmann::json list = nlohmann::json::array();
  for (Eigen::Index i = 0; i < n; ++i) list.push_back(v[i]);  // a float is exact as a JSON number
  return list;
}

}  // namespace

RemoteEnv::RemoteEnv(std::unique_ptr<remote::RemoteLink> link, const remote::Message& hello) : link_(std::move(link)) {
  spec_ = remote::get_spec(hello);
  const auto env = hello.header.find("env");
  if (env == hello.header.end() || !env->is_object()) throw Error(endpoint() + ": bad reply from the server: no env config");
  ConfigReader reader(*env, endpoint() + " (the server's resolved env)", "env");
  resolved_ = read_env_config(reader);
  const auto server = hello.header.find("server");
  server_ = server != hello.header.end() && server->is_string() ? server->get<std::string>() : "?";
}

RemoteEnv::~RemoteEnv() {
  try {
    link_->post(request("close"));
  } catch (...) {
    // The server frees the session when the connection drops anyway.
  }
}

const std::string& RemoteEnv::endpoint() const { return link_->endpoint(); }

remote::Message RemoteEnv::call(remote::Message request) {
  if (pending_) throw Error(endpoint() + ": a request was sent before the step begun was finished");
  return link_->call(std::move(request));
}

Observation RemoteEnv::reset(std::optional<std::uint64_t> seed) {
  remote::Message m = request("reset");
  if (seed) m.header["seed"] = *seed;
  return remote::get_observation(call(std::move(m)), spec_);
}

remote::Message RemoteEnv::step_request(const Action& action) const {
  if (pending_) throw Error(endpoint() + ": a step was sent before the step begun was finished");
  remote::Message m = request("step");
  if (spec_.action.discrete) m.header["action"] = action.index;
  else m.header["action"] = float_list(action.values.data(), action.values.size());
  return m;
}

StepResult RemoteEnv::step(const Action& action) { return remote::get_step_result(call(step_request(action)), spec_); }

bool RemoteEnv::begin_step(const Action& action) {
  pending_ = link_->send_request(step_request(action));
  return true;
}

void RemoteEnv::drop_caches() { (void)call(request("drop_caches")); }

StepOutcome RemoteEnv::finish_step(ObservationOut out) {
  if (!pending_) throw Error(endpoint() + ": finish_step without a step begun");
  const long long id = *pending_;
  pending_.reset();  // whatever happens next, the link is ready for a new request
  const StepResult r = remote::get_step_result(link_->wait_reply(id), spec_);
  copy_observation(r.observation, spec_.observation, out);
  return {r.reward, r.terminated, r.truncated, r.info};
}

RemoteRobotEnv::RemoteRobotEnv(std::unique_ptr<remote::RemoteLink> link, const remote::Message& hello, RobotInfo info)
    : RemoteEnv(std::move(link), hello), info_(std::move(info)) {}

StepResult RemoteRobotEnv::control_reply(remote::Message request) {
  return remote::get_step_result(call(std::move(request)), spec());
}

RobotSnapshot RemoteRobotEnv::robot_state() {
  return remote::get_robot_state(call(request("state")), static_cast<int>(info_.joints.size()));
}

StepResult RemoteRobotEnv::move_effector(const Eigen::Vector3f& position) {
  if (!position.allFinite()) throw Error(endpoint() + ": effector position must be finite numbers (m)");
  remote::Message m = request("position");
  m.header["position"] = float_list(position.data(), 3);
  return control_reply(std::move(m));
}

StepResult RemoteRobotEnv::set_joint_targets(const Eigen::VectorXf& targets) {
  if (!targets.allFinite()) throw Error(endpoint() + ": joint targets must be finite numbers");
  remote::Message m = request("joints");
  m.header["joints"] = float_list(targets.data(), targets.size());
  return control_reply(std::move(m));
}

void RemoteRobotEnv::camera_image(int camera, int width, int height, Image& out) {
  if (camera < 0 || camera >= static_cast<int>(info_.cameras.size()))
    throw Error("camera " + std::to_string(camera) + ": no such camera (this robot has " +
                std::to_string(info_.cameras.size()) + ")");
  const std::string& name = info_.cameras[static_cast<std::size_t>(camera)].name;
  remote::Message m = request("cameras");
  m.header["width"] = width;
  m.header["height"] = height;
  m.header["cameras"] = {name};
  out = remote::get_image(call(std::move(m)), name, width, height);
}

std::unique_ptr<RemoteEnv> connect_remote_env(const RemoteEnvConfig& link_config, const EnvConfig& env) {
  auto link = std::make_unique<remote::RemoteLink>(link_config);
  remote::Message hello = request("hello");
  hello.header["protocol"] = remote::protocol_version;
  hello.header["env"] = to_json(env);
  const remote::Message reply = link->call(std::move(hello));
  std::optional<RobotInfo> robot = remote::get_robot_info(reply);
  if (robot) return std::unique_ptr<RemoteEnv>(new RemoteRobotEnv(std::move(link), reply, std::move(*robot)));
  return std::unique_ptr<RemoteEnv>(new RemoteEnv(std::move(link), reply));
}

}  // namespace rdsim
