#pragma once
#include <memory>
#include <optional>
#include <string>

#include "rdsim/core/env.hpp"
#include "rdsim/core/env_caches.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/robot_control.hpp"
#include "rdsim/remote/message.hpp"
#include "rdsim/remote/remote_env_config.hpp"

// An Env whose simulation runs in an `rdsim serve` (possibly on another machine): every call is
// one request and its reply (docs/protocol.md), so train, replay and bench use a remote env like
// a local one, with bit-identical observations and rewards (float32 frames; JSON numbers that
// hold floats exactly). A robot env comes back as a RemoteRobotEnv, which is also a RobotControl,
// so `dynamic_cast<RobotControl*>` finds the capability exactly when the server's env has it.
//
// Not available over the link: Env::render (frames for people: use camera_image),
// step_physics_only, and EnvState (a checkpoint of a remote run resumes with fresh episodes).
// One RemoteEnv per thread; several in one process share one ZeroMQ I/O thread.
namespace rdsim {

namespace remote {
class RemoteLink;
}

class RemoteEnv : public Env, public EnvCaches {
public:
  ~RemoteEnv() override;  // closes the session (without waiting)

  const Spec& spec() const override { return spec_; }
  Observation reset(std::optional<std::uint64_t> seed = std::nullopt) override;
  StepResult step(const Action& action) override;
  // A step split around its round trip: begin_step sends the request, finish_step waits for the
  // reply (Env::begin_step), so a VecEnv of remote envs has all their requests in flight at once.
  bool begin_step(const Action& action) override;
  StepOutcome finish_step(ObservationOut out) override;
  // The server's env drops its engine caches (a drop_caches request), as a local env does at
  // every training update, so remote training matches local training over any length.
  void drop_caches() override;

  // The env config the server made the env from: every key with the value it uses.
  const EnvConfig& resolved_config() const { return resolved_; }
  // The server's name and version ("rdsim 0.1.0") and address.
  const std::string& server() const { return server_; }
  const std::string& endpoint() const;

protected:
  RemoteEnv(std::unique_ptr<remote::RemoteLink> link, const remote::Message& hello);
  remote::Message call(remote::Message request);
  remote::Message step_request(const Action& action) const;

private:
  friend std::unique_ptr<RemoteEnv> connect_remote_env(const RemoteEnvConfig&, const EnvConfig&);
  std::unique_ptr<remote::RemoteLink> link_;
  Spec spec_;
  EnvConfig resolved_;
  std::string server_;
  std::optional<long long> pending_;  // the request id of a step begun and not yet finished
};

class RemoteRobotEnv final : public RemoteEnv, public RobotControl {
public:
  const RobotInfo& robot_info() const override { return info_; }
  RobotSnapshot robot_state() override;
  StepResult move_effector(const Eigen::Vector3f& position) override;
  StepResult set_joint_targets(const Eigen::VectorXf& targets) override;
  // Sizes above remote::max_camera_side (1024) are refused by the server.
  void camera_image(int camera, int width, int height, Image& out) override;

private:
  friend std::unique_ptr<RemoteEnv> connect_remote_env(const RemoteEnvConfig&, const EnvConfig&);
  RemoteRobotEnv(std::unique_ptr<remote::RemoteLink> link, const remote::Message& hello, RobotInfo info);
  StepResult control_reply(remote::Message request);
  RobotInfo info_;
};

// Connects to link.remote, opens a session with `env` (sent as its resolved "env" object) and
// returns the env. rdsim::Error with the server's message (the same as a local config error,
// e.g. "hello: env.max_steps: expected ..."), for unreadable key files, a refused key, or no reply.
std::unique_ptr<RemoteEnv> connect_remote_env(const RemoteEnvConfig& link, const EnvConfig& env);

}  // namespace rdsim
