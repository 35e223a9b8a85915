// `rdsim teleop`: the teleoperation window on an in-process env or an `rdsim serve` session; both
// through the same Env and RobotControl interfaces.
#include "rdsim/app/teleop.hpp"

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "rdsim/app/env_source.hpp"
#include "rdsim/app/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_writer.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/remote_env.hpp"
#include "rdsim/teleop/scene_mirror.hpp"
#include "rdsim/teleop/teleop_session.hpp"

namespace rdsim {

int teleop_command(const TeleopOptions& o) {
  if (o.env.empty() == o.config_path.empty()) throw Error("teleop: give --env NAME or --config FILE");
  require_teleop_window();  // before connecting anywhere
  EnvConfig config;
  RemoteEnvConfig remote;
  if (!o.config_path.empty()) {
    const TrainConfig train = read_train_config(o.config_path);
    config = train.env;
    remote = train.remote;
  } else {
    config = default_env_config(o.env);
    config.random_target = !o.fixed_target;
    config.is_discrete = !o.continuous;
  }
  if (!o.connect.empty()) {
    remote.remote = o.connect;
    remote.server_key = o.server_key;
    remote.client_key = o.client_key;
  }
  std::unique_ptr<Env> env = open_env(config, remote);
  if (const auto* r = dynamic_cast<const RemoteEnv*>(env.get())) {
    config = r->resolved_config();  // what the server really runs
    std::printf("rdsim teleop: %s on %s (%s)\n", config.name.c_str(), r->endpoint().c_str(), r->server().c_str());
  }
  const nlohmann::json env_json = to_json(config);
  std::unique_ptr<DemoWriter> writer;
  if (!o.record_path.empty()) writer = std::make_unique<DemoWriter>(o.record_path, env_json, env->spec(), true);
  TeleopSession session(*env, o.seed, writer.get(), env_json);
  SceneMirror mirror(config);
  TeleopWindowOptions window = o.window;
  if (window.title == TeleopWindowOptions{}.title) window.title = "rdsim teleop: " + config.name;
  run_teleop_window(session, mirror, window);
  if (writer) std::printf("rdsim teleop: %s holds %lld demonstrations\n", o.record_path.c_str(), writer->episodes());
  return 0;
}

}  // namespace rdsim
