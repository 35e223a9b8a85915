#pragma once
#include <memory>
#include <nlohmann/json.hpp>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/remote/message.hpp"
#include "rdsim/remote/request.hpp"

// One client's environment on a server: made from the client's `hello`, then driven by its
// requests. No sockets here: the Server hands it parsed Requests and sends the Messages it
// returns, so every rule about what a client may ask is checked (and tested) in one place.
namespace rdsim::remote {

class Session {
public:
  // Reads hello's "env" object with the training-config code (envs/registry.hpp read_env_config:
  // the env's published defaults, the same checks and messages, "hello: env.<key>: ..."), refuses
  // what a server does not offer (urdf_root: the server uses its own assets; render_mode: frames
  // for people are the cameras request's; an observation above max_observation_bytes) and makes
  // the env. rdsim::Error with the message for the client.
  explicit Session(const Request& hello);
  ~Session();

  // The reply to hello: protocol, server version, the resolved env config, spec and robot.
  Message hello_reply(long long id) const;

  // The reply to reset, step, position, joints, cameras or state. rdsim::Error for a request this
  // session cannot serve now (step before the first reset, an action outside the spec, a robot
  // request on an env without a robot, an unknown camera, ...); the session stays usable.
  Message handle(const Request& request);

  const EnvConfig& config() const { return config_; }
  long long steps() const { return steps_; }

private:
  Message step_reply(const Request& q, const StepResult& r, bool with_state);
  RobotControl& robot(const Request& q);

  EnvConfig config_;
  std::unique_ptr<Env> env_;
  RobotControl* control_ = nullptr;  // env_ as a RobotControl, when it is one
  bool started_ = false;             // reset once
  long long steps_ = 0;
};

// A reply with just the request's id and kind.
Message reply_to(long long id, RequestKind kind);
// {"id": id (null when unknown), "error": what}
Message error_reply(const nlohmann::json& id, const std::string& what);

}  // namespace rdsim::remote
