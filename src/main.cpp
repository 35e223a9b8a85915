// rdsim: one binary for training, replaying and benchmarking robot learning.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "rdsim/app/bench_fps.hpp"
#include "rdsim/app/config_reference.hpp"
#include "rdsim/app/data_parallel.hpp"
#include "rdsim/app/envs.hpp"
#include "rdsim/app/process_communicator.hpp"
#include "rdsim/app/render.hpp"
#include "rdsim/app/replay.hpp"
#include "rdsim/app/train.hpp"
#include "rdsim/core/error.hpp"

namespace {

void add_train(CLI::App& app, rdsim::TrainOptions& o, std::uint64_t& seed, long long& timesteps, int& threads) {
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
  cmd->add_option("--threads", threads, "Override the config's num_threads (threads stepping the envs; "
                                        "results do not depend on it)")->check(CLI::Range(1, 4096));
  cmd->add_flag("-q,--quiet", o.quiet, "No progress line");
  cmd->footer("Data-parallel on several processes or machines: mpirun -np K rdsim train --config FILE "
              "(each rank its own envs; total_timesteps counts all ranks; rank 0 writes the run folder).");
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
                                              "included; median of several runs): one env on one thread, "
                                              "or a VecEnv on several (--threads, --scaling)");
  cmd->add_option("--env", o.envs, "Env to measure (repeatable; default: all)");
  cmd->add_option("--mode", o.modes, "Observation mode: ground_truth or raw_pixels (repeatable)")
      ->check(CLI::IsMember({"ground_truth", "raw_pixels"}));
  cmd->add_option("--image-size", o.image_sizes,
                  "Raw-pixel image side in pixels, one row each (repeatable; default: 64 and 224)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--runs", o.runs, "Runs per row; the median is reported")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--steps", o.steps, "Env steps per run")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--threads", o.threads,
                  "Threaded mode: a VecEnv of --num-envs envs on 1 and N threads; steps/s, speed-up, pool overhead")
      ->check(CLI::Range(1, 4096));
  cmd->add_flag("--scaling", o.scaling, "Threaded mode on 1, 2, 4, ... threads up to every core");
  cmd->add_option("--num-envs", o.num_envs, "Threaded mode: envs in the VecEnv (default: 4 per thread of the largest count)")
      ->check(CLI::Range(1, 4096));
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
  int train_threads = 0;
  add_train(app, train, train_seed, timesteps, train_threads);
  add_replay(app, replay, replay_seed);
  add_bench(app, bench);
  rdsim::RenderOptions render;
  add_render(app, render);
  app.add_subcommand("envs", "List the available environments");
  app.add_subcommand("config-reference",
                     "Print every config key with its type, default (per env), range and meaning "
                     "(markdown; docs/config.md is its output)");

  CLI11_PARSE(app, argc, argv);

  // The MPI job this process is a rank of (train only); after an error on one rank the others
  // are stopped instead of waiting for it in a collective.
  std::unique_ptr<rdsim::Communicator> comm;
  auto fail = [&](int code) {
    if (comm && comm->size() > 1) comm->abort(code);
    return code;
  };
  try {
    auto* sub = app.get_subcommands().front();
    const std::string name = sub->get_name();
    if (name == "train") {
      if (train.config_path.empty() && train.resume_dir.empty()) {
        throw rdsim::Error("train: give --config FILE or --resume DIR");
      }
      if (sub->count("--seed")) train.seed = train_seed;
      if (sub->count("--timesteps")) train.timesteps = timesteps;
      if (sub->count("--threads")) train.threads = train_threads;
      comm = rdsim::make_process_communicator();
      train.communicator = comm.get();
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
  } catch (const rdsim::RankExit& e) {  // rank 0 reports this error
    return fail(e.code);
  } catch (const rdsim::Error& e) {
    if (comm && comm->rank() > 0)
      std::fprintf(stderr, "rdsim: error (MPI rank %d): %s\n", comm->rank(), e.what());
    else
      std::fprintf(stderr, "rdsim: error: %s\n", e.what());
    return fail(1);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rdsim: internal error: %s\n", e.what());
    return fail(70);
  }
  return 0;
}
