// rdsim: one binary for training, replaying and benchmarking robot learning.
//
// Exit status: 0 success; 1 any error (bad input, bad command line, out of memory), reported as
// one line "rdsim: error: ..."; 130 / 143 a training run stopped by SIGINT / SIGTERM after saving
// its checkpoint (`rdsim train --resume DIR` continues it); 70 an internal error (a bug: please
// report it).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>

#include "rdsim/app/bench_fps.hpp"
#include "rdsim/app/demos.hpp"
#include "rdsim/app/bench_remote.hpp"
#include "rdsim/app/config_reference.hpp"
#include "rdsim/app/dashboard.hpp"
#include "rdsim/app/data_parallel.hpp"
#include "rdsim/app/envs.hpp"
#include "rdsim/app/keygen.hpp"
#include "rdsim/app/plot.hpp"
#include "rdsim/app/process_communicator.hpp"
#include "rdsim/app/render.hpp"
#include "rdsim/app/replay.hpp"
#include "rdsim/app/serve.hpp"
#include "rdsim/app/teleop.hpp"
#include "rdsim/app/train.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"

namespace {

// Command-line values that are config values too (seeds) are read by ConfigReader's rules, so
// "--seed -1" is an error, never 2^64 - 1.
struct SeedOption {
  std::string text;
  std::uint64_t value(const std::string& option) const {
    nlohmann::json j = nlohmann::json::object();
    j["seed"] = rdsim::json_from_option(text);
    rdsim::ConfigReader r(j, option);
    std::uint64_t seed = 0;
    r.read("seed", seed);
    return seed;
  }
};

void add_train(CLI::App& app, rdsim::TrainOptions& o, std::string& seed, std::string& timesteps, std::string& log_dir,
               double& max_memory, int& threads) {
  auto* cmd = app.add_subcommand("train", "Train a policy from a JSON config; writes progress.csv, "
                                          "episodes.csv, config.json, model.bin and checkpoint.bin to the run folder");
  auto* config = cmd->add_option("-c,--config", o.config_path, "JSON config file (see configs/)");
  auto* resume = cmd->add_option("--resume", o.resume_dir,
                                 "Continue the run in this folder from its last checkpoint");
  config->excludes(resume);
  resume->excludes(config);
  cmd->add_option("--seed", seed, "Override the config's seed (integer in [0, 2^64 - 1])");
  cmd->add_option("--timesteps", timesteps, "Override the config's total_timesteps (integer in [1, 1e12])");
  cmd->add_option("--log-dir", log_dir, "Override the config's log_dir (the run folder)");
  cmd->add_flag("--overwrite", o.overwrite, "Delete another run's files in the run folder first (else refused)");
  cmd->add_option("--max-memory", max_memory,
                  "Memory limit in GB for the run's estimated needs (default: 80% of the machine's memory)")
      ->check(CLI::Range(0.001, 1e6).description("in [0.001, 1e6]"));
  cmd->add_option("--threads", threads, "Override the config's num_threads (workers stepping the envs: threads, "
                                        "or for pixel envs processes; results do not depend on it)")->check(CLI::Range(1, 4096));
  cmd->add_flag("-q,--quiet", o.quiet, "No progress line");
  cmd->footer("Data-parallel on several processes or machines: mpirun -np K rdsim train --config FILE "
              "(each rank its own envs; total_timesteps counts all ranks; rank 0 writes the run folder).");
  cmd->add_option("--dashboard", o.dashboard,
                  "Serve the live dashboard of this run at HOST:PORT while training (e.g. 127.0.0.1:8097)");
}

void add_plot(CLI::App& app, rdsim::PlotOptions& o) {
  auto* cmd = app.add_subcommand("plot", "Draw the learning curves of runs (mean and band over each "
                                         "algorithm's runs) from their progress.csv, as PNG or SVG");
  cmd->add_option("runs", o.runs, "Run folders, or folders holding run folders")->required();
  cmd->add_option("-o,--out", o.out, "Figure to write: FILE.png or FILE.svg")->required();
  cmd->add_option("--metric", o.metric, "success, return, length, kl, or any progress.csv column")->capture_default_str();
  cmd->add_option("--x", o.x, "x axis: a progress.csv column (timesteps, updates, episodes, wall_time)")->capture_default_str();
  cmd->add_option("--band", o.band, "std: mean ± 1 standard deviation over runs; minmax: their range")
      ->check(CLI::IsMember({"std", "minmax"}))
      ->capture_default_str();
  cmd->add_option("--title", o.title, "Title (default: env and metric)");
  cmd->add_option("--x-max", o.x_max,
                  "Draw x up to this value only (e.g. 1e6 timesteps), cutting longer runs there; default: all")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--width", o.width, "Width in pixels")->check(CLI::Range(200, 8000))->capture_default_str();
  cmd->add_option("--height", o.height, "Height in pixels")->check(CLI::Range(150, 8000))->capture_default_str();
}

void add_dashboard(CLI::App& app, rdsim::DashboardCommandOptions& o) {
  auto* cmd = app.add_subcommand("dashboard", "Serve a live web page plotting the runs under the folders "
                                              "(progress.csv), updated as they train");
  cmd->add_option("runs", o.roots, "Folders holding run folders, or run folders (default: runs)");
  cmd->add_option("--bind", o.bind, "HOST:PORT to listen on (loopback unless you name another address)")
      ->capture_default_str();
  cmd->add_option("--poll-ms", o.poll_ms, "How often the page asks for new rows (ms)")
      ->check(CLI::Range(50, 60000))
      ->capture_default_str();
  cmd->add_option("--for", o.serve_s, "Stop after this many seconds (default: until Ctrl-C)")->check(CLI::NonNegativeNumber);
}

void add_replay(CLI::App& app, rdsim::ReplayOptions& o, SeedOption& seed, double& max_memory) {
  auto* cmd = app.add_subcommand("replay", "Run a saved model (model.bin) for N episodes and print "
                                           "return, length and success of each");
  cmd->add_option("model", o.model_path, "Model file written by `rdsim train`")->required();
  cmd->add_option("-n,--episodes", o.episodes, "Number of episodes")->check(CLI::Range(1, 1'000'000))->capture_default_str();
  cmd->add_option("--seed", seed.text, "Seed of the first episode (default: the model's training seed)");
  cmd->add_flag("--stochastic", o.stochastic, "Sample actions instead of taking the most likely one");
  cmd->add_option("--record", o.record_dir,
                  "Write what happens as PNG frames DIR/episode_NNN/frame_NNNN.png (robot envs; "
                  "size: env.render_width x render_height of the model's config)");
  cmd->add_option("--max-memory", max_memory, "Memory limit in GB (default: 80% of the machine's memory)")
      ->check(CLI::Range(0.001, 1e6).description("in [0.001, 1e6]"));
  cmd->add_option("--video", o.video_path,
                  "Write a video of the episodes, captioned with episode, step, return and success: "
                  "FILE.mp4 (H.264, when built with FFmpeg) or FILE.gif (robot envs)");
  cmd->add_option("--fps", o.video_fps, "Video frames per second")->check(CLI::Range(1, 240))->capture_default_str();
  cmd->add_option("--every", o.frame_every, "Keep every k-th step's frame (--record, --video)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--width", o.frame_width, "Frame width (default: the config's env.render_width)")->check(CLI::Range(8, 4096));
  cmd->add_option("--height", o.frame_height, "Frame height (default: env.render_height)")->check(CLI::Range(8, 4096));
}

void add_bench(CLI::App& app, rdsim::BenchFpsOptions& o) {
  auto* cmd = app.add_subcommand("bench-fps", "Measure env steps per second (random actions, resets "
                                              "included; median of several runs): one env on one thread, "
                                              "or a VecEnv on several (--threads, --scaling)");
  cmd->add_option("--env", o.envs, "Env to measure (repeatable; default: all)");
  cmd->add_option("--mode", o.modes, "Observation mode: ground_truth or raw_pixels (repeatable)")
      ->check(CLI::IsMember({"ground_truth", "raw_pixels"}));
  cmd->add_option("--image-size", o.image_sizes,
                  "Raw-pixel image side in pixels, one row each (repeatable; default: 64 and 224)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--runs", o.runs, "Runs per row; the median is reported")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--steps", o.steps, "Env steps per run")->check(CLI::Range(1LL, 1'000'000'000LL))->capture_default_str();
  cmd->add_option("--threads", o.threads,
                  "Threaded mode: a VecEnv of --num-envs envs on 1 and N threads; steps/s, speed-up, pool overhead")
      ->check(CLI::Range(1, 4096));
  cmd->add_flag("--scaling", o.scaling, "Threaded mode on 1, 2, 4, ... threads up to every core");
  cmd->add_option("--num-envs", o.num_envs, "Threaded mode: envs in the VecEnv (default: 4 per thread of the largest count)")
      ->check(CLI::Range(1, 4096));
  cmd->add_flag("--paper", o.paper,
                "Like-for-like Table 3: each robot env's paper preset (configs/paper/, the original's per-step "
                "work) next to its defaults, ground truth and 224x224 pixels");
  cmd->add_option("--json", o.json_path, "Also write the results as JSON to this file ('-' = stdout)")
      ->expected(0, 1)
      ->default_str("-");
}

void add_render(CLI::App& app, rdsim::RenderOptions& o, SeedOption& seed) {
  auto* cmd = app.add_subcommand("render", "Write the raw-pixel observation an env gives after reset as a PNG");
  cmd->add_option("--env", o.env, "Env name (see `rdsim envs`; needs pixels)")->required();
  cmd->add_option("--out", o.out_path, "PNG file to write")->required();
  cmd->add_option("--view", o.view, "Camera: 1 = main, 2 = second (multi-view) camera")->check(CLI::IsMember({1, 2}))->capture_default_str();
  cmd->add_option("--width", o.width, "Image width in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--height", o.height, "Image height in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--seed", seed.text, "Reset seed (default 0)");
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
  cmd->add_option("--envs", o.envs, "Envs of the one-client VecEnv rows (1: none)")->check(CLI::Range(1, 64))->capture_default_str();
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

// Levenshtein distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The first word is the command; an unknown one is named with the closest valid one.
void check_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return;  // CLI11 says a command is required
  const std::string word = argv[1];
  if (word[0] == '-') {
    if (word == "-h" || word == "--help" || word == "--version") return;
    throw rdsim::Error("unknown option \"" + rdsim::one_line(word, 40) + "\" before the command (rdsim --help)");
  }
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
  if (std::find(names.begin(), names.end(), word) != names.end()) return;
  // A command the word begins ("bench" -> "bench-fps"), else the fewest edits away.
  std::string closest = names.front(), list;
  for (const auto& n : names) {
    if (edit_distance(word, n) < edit_distance(word, closest)) closest = n;
    list += (list.empty() ? "" : ", ") + n;
  }
  for (const auto& n : names)
    if (n.rfind(word, 0) == 0) {
      closest = n;  // the first such command ("bench" -> "bench-fps", not "bench-remote")
      break;
    }
  throw rdsim::Error("unknown command \"" + rdsim::one_line(word, 40) + "\"" +
                     (edit_distance(word, closest) <= 3 || closest.rfind(word, 0) == 0 ? " (did you mean \"" + closest + "\"?)"
                                                                         : std::string()) +
                     "; commands: " + list + " (rdsim --help)");
}

int fail(const std::string& message) {
  std::fprintf(stderr, "rdsim: error: %s\n", rdsim::one_line(message, 2000).c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rdsim " RDSIM_VERSION " - robot deep reinforcement learning simulator\n"
               "Exit status: 0 done, 1 error (one line \"rdsim: error: ...\"), 130/143 training stopped by "
               "SIGINT/SIGTERM after saving (continue with train --resume), 70 internal error"};
  app.require_subcommand(1);
  app.set_version_flag("--version", RDSIM_VERSION);

  rdsim::TrainOptions train;
  rdsim::ReplayOptions replay;
  rdsim::BenchFpsOptions bench;
  rdsim::RenderOptions render;
  std::string train_seed, timesteps, log_dir;
  SeedOption replay_seed, render_seed;
  double train_memory = 0.0, replay_memory = 0.0;
  int train_threads = 0;
  add_train(app, train, train_seed, timesteps, log_dir, train_memory, train_threads);
  add_replay(app, replay, replay_seed, replay_memory);
  add_bench(app, bench);
  add_render(app, render, render_seed);
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
  rdsim::DashboardCommandOptions dashboard;
  add_dashboard(app, dashboard);
  rdsim::PlotOptions plot;
  add_plot(app, plot);

  // The MPI job this process is a rank of (train only); after an error on one rank the others
  // are stopped instead of waiting for it in a collective.
  std::unique_ptr<rdsim::Communicator> comm;
  auto stop = [&](int code) {
    if (comm && comm->size() > 1) comm->abort(code);
    return code;
  };
  try {
    check_command(app, argc, argv);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
      return fail(std::string(e.what()) + " (rdsim " +
                  (app.get_subcommands().empty() ? std::string("--help") : app.get_subcommands().front()->get_name() + " --help") +
                  ")");
    }
    auto* sub = app.get_subcommands().front();
    const std::string name = sub->get_name();
    if (name == "train") {
      if (train.config_path.empty() && train.resume_dir.empty()) throw rdsim::Error("train: give --config FILE or --resume DIR");
      if (sub->count("--seed")) train.overrides.push_back({"--seed", "seed", train_seed});
      if (sub->count("--timesteps")) train.overrides.push_back({"--timesteps", "total_timesteps", timesteps});
      if (sub->count("--log-dir")) train.overrides.push_back({"--log-dir", "log_dir", log_dir});
      if (sub->count("--max-memory")) train.max_memory_gb = train_memory;
      if (sub->count("--threads")) train.threads = train_threads;
      comm = rdsim::make_process_communicator();
      train.communicator = comm.get();
      return rdsim::train_command(train);
    }
    if (name == "replay") {
      if (sub->count("--seed")) replay.seed = replay_seed.value("--seed");
      if (sub->count("--max-memory")) replay.max_memory_gb = replay_memory;
      return rdsim::replay_command(replay);
    }
    if (name == "bench-fps") {
      if (sub->count("--json") && bench.json_path.empty()) bench.json_path = "-";
      return rdsim::bench_fps_command(bench);
    }
    if (name == "envs") return rdsim::envs_command();
    if (name == "config-reference") return rdsim::config_reference_command();
    if (name == "dashboard") return rdsim::dashboard_command(dashboard);
    if (name == "plot") return rdsim::plot_command(plot);
    if (name == "render") {
      if (sub->count("--seed")) render.seed = render_seed.value("--seed");
      return rdsim::render_command(render);
    }
    if (name == "demos") {
      if (sub->get_subcommands().front()->get_name() == "info") return rdsim::demos_info_command(demos_info_path);
      return rdsim::demos_record_command(demos_record);
    }
    if (name == "serve") return rdsim::serve_command(serve);
    if (name == "keygen") return rdsim::keygen_command(keygen);
    if (name == "bench-remote") return rdsim::bench_remote_command(bench_remote);
    if (name == "teleop") return rdsim::teleop_command(teleop);
  } catch (const rdsim::RankExit& e) {  // rank 0 reports this error
    return e.job_knows ? e.code : stop(e.code);
  } catch (const rdsim::JobError& e) {  // every rank knows: each returns, MPI finalises normally
    return fail(e.what());
  } catch (const rdsim::Error& e) {
    if (comm && comm->rank() > 0) return stop(fail("(MPI rank " + std::to_string(comm->rank()) + ") " + e.what()));
    return stop(fail(e.what()));
  } catch (const std::bad_alloc&) {
    return stop(fail("out of memory: the machine (or ulimit -v) could not provide what this command needs; "
                     "use smaller sizes or lower --max-memory so the run is refused up front"));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rdsim: internal error: %s\n", rdsim::one_line(e.what(), 2000).c_str());
    return stop(70);
  }
  return 0;
}
