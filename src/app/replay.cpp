// `rdsim replay`: runs a saved policy from its model file alone.
#include "rdsim/app/replay.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <sstream>

#include "rdsim/algorithms/algorithm.hpp"
#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/training/env_source.hpp"
#include "rdsim/training/memory_check.hpp"
#include "rdsim/training/model_file.hpp"
#include "rdsim/training/policy_episodes.hpp"
#include "rdsim/training/train_config.hpp"
#include "rdsim/video/frame_capture.hpp"

namespace rdsim {
namespace {

// How the header line names where a model trained on remote envs runs.
std::string where_replayed(const std::string& trained_on, bool remote) {
  if (trained_on.empty()) return "";
  if (remote) return ", on the server " + trained_on;
  return ", on a local env (trained on the server " + trained_on + "; --remote replays there)";
}

}  // namespace

int replay_command(const ReplayOptions& o) {
  const ModelFile file = read_model_file(o.model_path);
  TrainConfig config = parse_train_config(file.config, o.model_path + " (embedded config)", "replay");
  if (!o.record_dir.empty() || !o.video_path.empty()) config.env.render_mode = RenderMode::RgbArray;
  if (o.frame_width > 0) config.env.render_width = o.frame_width;
  if (o.frame_height > 0) config.env.render_height = o.frame_height;
  config.num_envs = 1;
  // config.env holds the values the server used, so a local env is the same env: the weights replay
  // without the server (it may be stopped, or the keys elsewhere).
  const std::string trained_on = config.remote.remote;
  if (!o.remote) config.remote = RemoteEnvConfig{};
  check_memory(estimate_training_memory(config, config_spec(config)), memory_limit(o.max_memory_gb), o.model_path);
  auto env = open_env(config.env, config.remote);
  check_model_spec(file, env->spec(), o.model_path);
  FrameCapture frames({o.record_dir, o.video_path, o.video_fps, o.frame_every}, *env, o.episodes,
                      config.env.render_width, config.env.render_height);
  auto algo = make_algorithm(config.algorithm, config.seed, env->spec());
  std::istringstream in(file.payload);
  algo->load(in, false, o.model_path);  // a checkpoint's payload starts with the same weights
  if (file.kind == ModelKind::Model && in.peek() != std::char_traits<char>::eof())
    throw Error(o.model_path + ": file is damaged (unexpected trailing data after the weights)");

  const std::uint64_t seed = o.seed.value_or(config.seed);
  std::printf("%s (%s on %s), %d episode%s, %s actions%s\n", o.model_path.c_str(), config.algorithm.name().c_str(),
              config.env.name.c_str(), o.episodes, o.episodes == 1 ? "" : "s", o.stochastic ? "sampled" : "deterministic",
              where_replayed(trained_on, o.remote).c_str());
  PolicyEpisodeHooks hooks;
  hooks.on_start = [&](int k) {
    frames.start_episode(k + 1);
    frames.capture(0, 0.0, false, false);
  };
  hooks.on_step = [&](long long length, double ret, bool success, bool done) { frames.capture(length, ret, success, done); };
  hooks.on_end = [](int k, const EpisodeOutcome& e) {
    std::printf("episode %d: return %.2f, length %lld, success %s\n", k + 1, e.episode_return, e.length,
                e.success ? "yes" : "no");
  };
  double sum_return = 0, sum_length = 0, successes = 0;
  for (const EpisodeOutcome& e : run_policy_episodes(*env, *algo, o.episodes, seed, !o.stochastic, hooks)) {
    sum_return += e.episode_return;
    sum_length += static_cast<double>(e.length);
    successes += e.success ? 1 : 0;
  }
  std::printf("mean return %.2f, mean length %.1f, success rate %.2f over %d episodes\n", sum_return / o.episodes,
              sum_length / o.episodes, successes / o.episodes, o.episodes);
  frames.close();
  if (!o.record_dir.empty()) std::printf("wrote %lld frames to %s\n", frames.pictures(), o.record_dir.c_str());
  if (!o.video_path.empty()) std::printf("wrote %s (%s)\n", o.video_path.c_str(), frames.video_format().c_str());
  return 0;
}

Command replay_command_entry() {
  return {"replay", "Run a saved model (model.bin) for N episodes and print return, length and success of each",
          [](CLI::App& cmd) -> std::function<int()> {
            struct Line {
              ReplayOptions o;
              std::string seed;
              double max_memory = 0.0;
            };
            auto l = std::make_shared<Line>();
            ReplayOptions& o = l->o;
            cmd.add_option("model", o.model_path, "Model file written by `rdsim train`")->required();
            cmd.add_option("-n,--episodes", o.episodes, "Number of episodes")->check(CLI::Range(1, 1'000'000))->capture_default_str();
            cmd.add_option("--seed", l->seed, "Seed of the first episode (default: the model's training seed)")->type_name("INT");
            cmd.add_flag("--stochastic", o.stochastic, "Sample actions instead of taking the most likely one");
            cmd.add_option("--record", o.record_dir,
                           "Write what happens as PNG frames DIR/episode_NNN/frame_NNNN.png (robot envs; "
                           "size: env.render_width x render_height of the model's config)");
            cmd.add_option("--max-memory", l->max_memory, "Memory limit in GB (default: 80% of the machine's memory)")
                ->check(CLI::Range(0.001, 1e6).description("in [0.001, 1e6]"));
            cmd.add_option("--video", o.video_path,
                           "Write a video of the episodes, captioned with episode, step, return and success: "
                           "FILE.mp4 (H.264, when built with FFmpeg) or FILE.gif (robot envs)");
            cmd.add_option("--fps", o.video_fps, "Video frames per second")->check(CLI::Range(1, 240))->capture_default_str();
            cmd.add_option("--every", o.frame_every, "Keep every k-th step's frame (--record, --video)")
                ->check(CLI::Range(1, 1000000))
                ->capture_default_str();
            cmd.add_flag("--remote", o.remote,
                         "A model trained on remote envs: replay on the server its config names (default: a local env, "
                         "the same env the server ran)");
            cmd.add_option("--width", o.frame_width, "Frame width (default: the config's env.render_width)")->check(CLI::Range(8, 4096));
            cmd.add_option("--height", o.frame_height, "Frame height (default: env.render_height)")->check(CLI::Range(8, 4096));
            return [l, &cmd] {
              if (cmd.count("--seed")) l->o.seed = seed_from_option(l->seed, "--seed");
              if (cmd.count("--max-memory")) l->o.max_memory_gb = l->max_memory;
              return replay_command(l->o);
            };
          }};
}

}  // namespace rdsim
