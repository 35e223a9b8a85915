#pragma once
#include <cstdint>
#include <string>

#include "rdsim/teleop/teleop_window.hpp"

// `rdsim teleop`: drive an env's robot by hand and record demonstrations (src/app/teleop.cpp; the
// window: rdsim/teleop/teleop_window.hpp).
namespace rdsim {

struct TeleopOptions {
  std::string env;             // in-process env by name: its default options, random targets (below)
  std::string config_path;     // or the "env" object of this training config (which may name a server)
  std::string connect;         // or the env of an `rdsim serve` at tcp://HOST:PORT (with env or config)
  std::string server_key;      // the server's public key file (rdsim keygen NAME.key)
  std::string client_key;      // this client's secret key file (NAME.key_secret)
  std::string record_path;     // demonstrations are appended here (created when missing)
  std::uint64_t seed = 0;      // episode k (0-based) starts from reset(seed + k)
  bool fixed_target = false;   // --env: the env's default target (no random_target)
  bool continuous = false;     // --env: Box(3) actions
  TeleopWindowOptions window;
};
int teleop_command(const TeleopOptions& options);

}  // namespace rdsim
