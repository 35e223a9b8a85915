// `rdsim teleop`: the teleoperation window on an in-process env or an `rdsim serve` session; both
// through the same Env and RobotControl interfaces.
#include "rdsim/app/teleop.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_writer.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/remote_env.hpp"
#include "rdsim/teleop/scene_mirror.hpp"
#include "rdsim/teleop/teleop_session.hpp"
#include "rdsim/training/env_source.hpp"
#include "rdsim/training/train_config.hpp"

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
    if (auto* reach = config.find<ReachOptions>()) {
      reach->random_target = !o.fixed_target;
      config.is_discrete = !o.continuous;  // the manipulation tasks' actions are Box only
    }
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
  // The file is created at once (a wrong path or a file of another env fails before the window
  // opens), and removed again if the session recorded nothing into it (first contact, item 10).
  std::error_code ec;
  const bool existed = !o.record_path.empty() && std::filesystem::exists(o.record_path, ec);
  if (!o.record_path.empty()) writer = std::make_unique<DemoWriter>(o.record_path, env_json, env->spec(), true);
  TeleopSession session(*env, o.seed, writer.get(), env_json);
  SceneMirror mirror(config);
  TeleopWindowOptions window = o.window;
  if (window.title == TeleopWindowOptions{}.title) window.title = "rdsim teleop: " + config.name;
  run_teleop_window(session, mirror, window);
  if (writer && !existed && writer->episodes() == 0) {
    writer.reset();  // releases the file's lock
    std::filesystem::remove(o.record_path, ec);
    std::printf("rdsim teleop: nothing was recorded; %s not kept\n", o.record_path.c_str());
  } else if (writer) {
    std::printf("rdsim teleop: %s holds %lld demonstrations\n", o.record_path.c_str(), writer->episodes());
  }
  return 0;
}

Command teleop_command_entry() {
  return {"teleop", "Drive an env's robot by hand in a window (keys: the env's actions; sliders: "
          "effector target and joints) and record demonstrations",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<TeleopOptions>();
            auto* env = cmd.add_option("--env", o->env, "Env name (its default options, random targets)");
            auto* config = cmd.add_option("--config", o->config_path, "Or the \"env\" object of this training config");
            env->excludes(config);
            cmd.add_option("--connect", o->connect, "Drive the env of an `rdsim serve` at tcp://HOST:PORT instead of one in this process");
            cmd.add_option("--server-key", o->server_key, "--connect: the server's public key file (rdsim keygen NAME.key)");
            cmd.add_option("--client-key", o->client_key, "--connect: this client's secret key file (NAME.key_secret)");
            cmd.add_option("--record", o->record_path, "Demonstration file the recorded episodes are appended to (created when missing)");
            cmd.add_option("--seed", o->seed, "Episode k starts from reset(seed + k)")->capture_default_str();
            cmd.add_flag("--fixed-target", o->fixed_target, "--env: keep the default target (no random_target)");
            cmd.add_flag("--continuous", o->continuous, "--env: Box(3) actions instead of Discrete(6)");
            cmd.add_option("--screenshot", o->window.screenshot_path, "PNG file the P key writes")->capture_default_str();
            cmd.add_option("--width", o->window.width, "Window width")->check(CLI::Range(640, 8192))->capture_default_str();
            cmd.add_option("--height", o->window.height, "Window height")->check(CLI::Range(480, 8192))->capture_default_str();
            cmd.add_option("--renderer", o->window.renderer, "Renderer of the 3D view: osmesa, egl or auto")
                ->check(CLI::IsMember({"osmesa", "egl", "auto"}))
                ->capture_default_str();
            cmd.add_option("--frames", o->window.max_frames, "Close after this many frames (0: when closed)")->capture_default_str();
            return [o] { return teleop_command(*o); };
          }};
}

}  // namespace rdsim
