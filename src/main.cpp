// rdsim: one binary for training, replaying and benchmarking robot learning.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "rdsim/app/bench_fps.hpp"
#include "rdsim/app/demos.hpp"
#include "rdsim/app/bench_remote.hpp"
#include "rdsim/app/config_reference.hpp"
#include "rdsim/app/envs.hpp"
#include "rdsim/app/keygen.hpp"
#include "rdsim/app/render.hpp"
#include "rdsim/app/replay.hpp"
#include "rdsim/app/serve.hpp"
#include "rdsim/app/teleop.hpp"
#include "rdsim/app/train.hpp"
#include "rdsim/core/error.hpp"

namespace {

void add_train(CLI::App& app, rdsim::TrainOptions& o, std::uint64_t& seed, long long& timesteps) {
  auto* cmd = app.add_subcommand("train", "Train a policy from a JSON config; writes progress.csv, "
                                          "episodes.csv, config.json and model.bin to the run folder");
  auto* config = cmd->add_option("-c,--config", o.config_path, "JSON config file (see configs/)");
  auto* resume = cmd->add_option("--resume", o.resume_dir,
                                 "Continue the run in this folder from its last checkpoint");
  config->excludes(resume);
  resume->excludes(config);
  cmd->add_option("--seed", seed, "Override the config's seed");
  cmd->add_option("--timesteps", timesteps, "Override the config's total_timesteps")->check(CLI::PositiveNumber);
  cmd->add_option("--log-dir", o.log_dir, "Override the config's log_dir (the run folder)");
  cmd->add_flag("-q,--quiet", o.quiet, "No progress line");
}

void add_replay(CLI::App& app, rdsim::ReplayOptions& o, std::uint64_t& seed) {
  auto* cmd = app.add_subcommand("replay", "Run a saved model (model.bin) for N episodes and print "
                                           "return, length and success of each");
  cmd->add_option("model", o.model_path, "Model file written by `rdsim train`")->required();
  cmd->add_option("-n,--episodes", o.episodes, "Number of episodes")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--seed", seed, "Seed of the first episode (default: the model's training seed)");
  cmd->add_flag("--stochastic", o.stochastic, "Sample actions instead of taking the most likely one");
  cmd->add_option("--record", o.record_dir,
                  "Write what happens as PNG frames DIR/episode_NNN/frame_NNNN.png (robot envs; "
                  "size: env.render_width x render_height of the model's config)");
}

void add_bench(CLI::App& app, rdsim::BenchFpsOptions& o) {
  auto* cmd = app.add_subcommand("bench-fps", "Measure env steps per second (random actions, resets "
                                              "included; median of several runs), one thread");
  cmd->add_option("--env", o.envs, "Env to measure (repeatable; default: all)");
  cmd->add_option("--mode", o.modes, "Observation mode: ground_truth or raw_pixels (repeatable)")
      ->check(CLI::IsMember({"ground_truth", "raw_pixels"}));
  cmd->add_option("--image-size", o.image_sizes,
                  "Raw-pixel image side in pixels, one row each (repeatable; default: 64 and 224)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--runs", o.runs, "Runs per row; the median is reported")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--steps", o.steps, "Env steps per run")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--json", o.json_path, "Also write the results as JSON to this file ('-' = stdout)")
      ->expected(0, 1)
      ->default_str("-");
}

void add_render(CLI::App& app, rdsim::RenderOptions& o) {
  auto* cmd = app.add_subcommand("render", "Write the raw-pixel observation an env gives after reset as a PNG");
  cmd->add_option("--env", o.env, "Env name (see `rdsim envs`; needs pixels)")->required();
  cmd->add_option("--out", o.out_path, "PNG file to write")->required();
  cmd->add_option("--view", o.view, "Camera: 1 = main, 2 = second (multi-view) camera")->check(CLI::IsMember({1, 2}))->capture_default_str();
  cmd->add_option("--width", o.width, "Image width in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--height", o.height, "Image height in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--seed", o.seed, "Reset seed")->capture_default_str();
  cmd->add_flag("--random-target", o.random_target, "Randomise the target at reset (env.random_target)");
}

void add_demos(CLI::App& app, std::string& info_path, rdsim::DemosRecordOptions& o) {
  auto* cmd = app.add_subcommand("demos", "Demonstration files: what one holds, recording the scripted expert");
  cmd->require_subcommand(1);
  auto* info = cmd->add_subcommand("info", "Print a demonstration file's env, episodes, steps, success rate and mean return");
  info->add_option("file", info_path, "Demonstration file")->required();
  auto* record = cmd->add_subcommand("record", "Record episodes of the scripted expert (privileged state, the env's own actions)");
  record->add_flag("--expert", o.expert, "Use the scripted expert (the only recorder here; people record with `rdsim teleop --record`)")
      ->required();
  auto* env = record->add_option("--env", o.env, "Env name (its default options, random targets)");
  auto* config = record->add_option("--config", o.config_path, "Or take the \"env\" object of this training config");
  env->excludes(config);
  record->add_option("-n,--episodes", o.episodes, "Episodes to write")->check(CLI::Range(1, 1000000))->capture_default_str();
  record->add_option("--out", o.out_path, "Demonstration file to write")->required();
  record->add_option("--seed", o.seed, "Episode k starts from reset(seed + k)")->capture_default_str();
  record->add_flag("--append", o.append, "Add to an existing file of the same env");
  record->add_flag("--fixed-target", o.fixed_target, "--env: keep the default target (no random_target)");
  record->add_flag("--continuous", o.continuous, "--env: Box(3) actions instead of Discrete(6)");
  record->add_flag("--only-successes", o.only_successes, "Write successful episodes only");
  record->add_flag("-q,--quiet", o.quiet, "No line per episode");
}

void add_serve(CLI::App& app, rdsim::ServeOptions& o) {
  auto* cmd = app.add_subcommand("serve", "Host environments for remote clients (docs/protocol.md; "
                                          "tools/rdsim_client.py, or \"remote\" in a config's env) until Ctrl-C");
  cmd->add_option("--bind", o.bind, "Address to listen on (port * = any free port; printed on start)")->capture_default_str();
  cmd->add_option("--keys", o.keys_dir,
                  "Folder with server.key_secret and clients/*.key (rdsim keygen): CurveZMQ authentication and encryption");
  cmd->add_flag("--insecure", o.insecure, "Plain text without --keys (allowed on loopback addresses only)");
  cmd->add_option("--max-sessions", o.max_sessions, "Most envs served at once")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--idle-timeout", o.idle_timeout, "Seconds without requests after which a session is closed")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

void add_keygen(CLI::App& app, rdsim::KeygenOptions& o) {
  auto* cmd = app.add_subcommand("keygen", "Write a CurveZMQ key pair: DIR/NAME.key (public) and DIR/NAME.key_secret "
                                           "(secret, mode 0600)");
  cmd->add_option("name", o.name, "Key name (letters, digits, _ - .)")->required();
  cmd->add_option("--dir", o.dir, "Folder to write the two files to")->capture_default_str();
}

void add_bench_remote(CLI::App& app, rdsim::BenchRemoteOptions& o) {
  auto* cmd = app.add_subcommand("bench-remote", "Measure remote env steps/s and round-trip latency over loopback "
                                                 "(CurveZMQ on) next to in-process steps/s, in one run");
  cmd->add_option("--env", o.env, "Env to measure")->capture_default_str();
  cmd->add_option("--steps", o.steps, "Env steps per measurement")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--clients", o.clients, "Clients of the concurrent row")->check(CLI::Range(1, 64))->capture_default_str();
  cmd->add_option("--image-size", o.image_size, "Side of the raw-pixel row's images")->check(CLI::Range(8, 1024))->capture_default_str();
  cmd->add_option("--runs", o.runs, "Runs per row; the median is reported")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_flag("--insecure", o.insecure, "Plain text instead of CurveZMQ (to see what encryption costs)");
  cmd->add_option("--json", o.json_path, "Also write the results as JSON to this file ('-' = stdout)");
}

void add_teleop(CLI::App& app, rdsim::TeleopOptions& o) {
  auto* cmd = app.add_subcommand("teleop", "Drive an env's robot by hand in a window (keys: the env's actions; sliders: "
                                           "effector target and joints) and record demonstrations");
  auto* env = cmd->add_option("--env", o.env, "Env name (its default options, random targets)");
  auto* config = cmd->add_option("--config", o.config_path, "Or the \"env\" object of this training config");
  env->excludes(config);
  cmd->add_option("--connect", o.connect, "Drive the env of an `rdsim serve` at tcp://HOST:PORT instead of one in this process");
  cmd->add_option("--server-key", o.server_key, "--connect: the server's public key file (rdsim keygen NAME.key)");
  cmd->add_option("--client-key", o.client_key, "--connect: this client's secret key file (NAME.key_secret)");
  cmd->add_option("--record", o.record_path, "Demonstration file the recorded episodes are appended to (created when missing)");
  cmd->add_option("--seed", o.seed, "Episode k starts from reset(seed + k)")->capture_default_str();
  cmd->add_flag("--fixed-target", o.fixed_target, "--env: keep the default target (no random_target)");
  cmd->add_flag("--continuous", o.continuous, "--env: Box(3) actions instead of Discrete(6)");
  cmd->add_option("--screenshot", o.window.screenshot_path, "PNG file the P key writes")->capture_default_str();
  cmd->add_option("--width", o.window.width, "Window width")->check(CLI::Range(640, 8192))->capture_default_str();
  cmd->add_option("--height", o.window.height, "Window height")->check(CLI::Range(480, 8192))->capture_default_str();
  cmd->add_option("--renderer", o.window.renderer, "Renderer of the 3D view: osmesa, egl or auto")
      ->check(CLI::IsMember({"osmesa", "egl", "auto"}))
      ->capture_default_str();
  cmd->add_option("--frames", o.window.max_frames, "Close after this many frames (0: when closed)")->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rdsim " RDSIM_VERSION " - robot deep reinforcement learning simulator"};
  app.require_subcommand(1);
  app.set_version_flag("--version", RDSIM_VERSION);

  rdsim::TrainOptions train;
  rdsim::ReplayOptions replay;
  rdsim::BenchFpsOptions bench;
  std::uint64_t train_seed = 0, replay_seed = 0;
  long long timesteps = 0;
  add_train(app, train, train_seed, timesteps);
  add_replay(app, replay, replay_seed);
  add_bench(app, bench);
  rdsim::RenderOptions render;
  add_render(app, render);
  app.add_subcommand("envs", "List the available environments");
  std::string demos_info_path;
  rdsim::DemosRecordOptions demos_record;
  add_demos(app, demos_info_path, demos_record);
  app.add_subcommand("config-reference",
                     "Print every config key with its type, default (per env), range and meaning "
                     "(markdown; docs/config.md is its output)");
  rdsim::ServeOptions serve;
  add_serve(app, serve);
  rdsim::KeygenOptions keygen;
  add_keygen(app, keygen);
  rdsim::BenchRemoteOptions bench_remote;
  add_bench_remote(app, bench_remote);
  rdsim::TeleopOptions teleop;
  add_teleop(app, teleop);

  CLI11_PARSE(app, argc, argv);

  try {
    auto* sub = app.get_subcommands().front();
    const std::string name = sub->get_name();
    if (name == "train") {
      if (train.config_path.empty() && train.resume_dir.empty()) {
        throw rdsim::Error("train: give --config FILE or --resume DIR");
      }
      if (sub->count("--seed")) train.seed = train_seed;
      if (sub->count("--timesteps")) train.timesteps = timesteps;
      return rdsim::train_command(train);
    }
    if (name == "replay") {
      if (sub->count("--seed")) replay.seed = replay_seed;
      return rdsim::replay_command(replay);
    }
    if (name == "bench-fps") {
      if (sub->count("--json") && bench.json_path.empty()) bench.json_path = "-";
      return rdsim::bench_fps_command(bench);
    }
    if (name == "envs") return rdsim::envs_command();
    if (name == "config-reference") return rdsim::config_reference_command();
    if (name == "render") return rdsim::render_command(render);
    if (name == "demos") {
      if (sub->get_subcommands().front()->get_name() == "info") return rdsim::demos_info_command(demos_info_path);
      return rdsim::demos_record_command(demos_record);
    }
    if (name == "serve") return rdsim::serve_command(serve);
    if (name == "keygen") return rdsim::keygen_command(keygen);
    if (name == "bench-remote") return rdsim::bench_remote_command(bench_remote);
    if (name == "teleop") return rdsim::teleop_command(teleop);
  } catch (const rdsim::Error& e) {
    std::fprintf(stderr, "rdsim: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rdsim: internal error: %s\n", e.what());
    return 70;
  }
  return 0;
}
