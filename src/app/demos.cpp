// `rdsim demos`: what a demonstration file holds, and recording the scripted expert.
#include "rdsim/app/demos.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_summary.hpp"
#include "rdsim/demos/demo_writer.hpp"
#include "rdsim/envs/manipulation/manipulation_expert.hpp"
#include "rdsim/envs/scripted_expert.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {

int demos_info_command(const std::string& path) {
  const DemoFile f = read_demo_file(path);
  const DemoSummary s = summarize(f);
  std::printf("%s: rdsim demonstrations, format version %u, written by rdsim %s\n", path.c_str(), f.version,
              f.rdsim_version.c_str());
  std::printf("env          %s %s\n", f.spec.env_name.c_str(), f.env_config.dump().c_str());
  std::printf("spaces       observations %s, actions %s, step limit %d\n", describe_observation_space(f.spec.observation).c_str(),
              describe_action_space(f.spec.action).c_str(), f.spec.max_episode_steps);
  std::printf("episodes     %d (%d scripted, %d human)\n", s.episodes, s.scripted, s.human);
  std::printf("steps        %lld (mean length %.1f)\n", s.steps, s.mean_length);
  std::printf("success rate %.2f\n", s.success_rate);
  std::printf("mean return  %.2f\n", s.mean_return);
  std::printf("endings      %d terminated, %d truncated, %d stopped by hand; %d with a collision\n", s.terminated,
              s.truncated, s.stopped, s.collisions);
  if (f.interrupted_bytes > 0)
    std::printf("note         %llu bytes after the last complete episode (a recording cut short) are ignored\n",
                static_cast<unsigned long long>(f.interrupted_bytes));
  return 0;
}

int demos_record_command(const DemosRecordOptions& o) {
  // The scripted expert is the only recorder here, so --expert is optional (kept for the commands
  // already written down); people record with `rdsim teleop --record`.
  if (o.env.empty() == o.config_path.empty()) throw Error("demos record: give --env NAME or --config FILE");
  EnvConfig env_config;
  if (!o.config_path.empty()) {
    env_config = read_train_config(o.config_path).env;
  } else {
    env_config = default_env_config(o.env);
    if (auto* reach = env_config.find<ReachOptions>()) {
      reach->random_target = !o.fixed_target;
      env_config.is_discrete = !o.continuous;  // the manipulation tasks' actions are Box only
    }
  }
  auto env = make_env(env_config);
  const ActionSpace& space = env->spec().action;
  // NaN passes CLI11's range check and would record the expert's own actions without a word.
  if (!(o.action_noise >= 0.0 && o.action_noise <= 10.0))
    throw Error("demos record: --action-noise: expected a standard deviation from 0 to 10, got " + std::to_string(o.action_noise));
  if (o.action_noise > 0.0 && space.discrete)
    throw Error("demos record: --action-noise: expected Box actions (" + env->spec().env_name + " has Discrete ones)");
  if (!(o.missed_grasps >= 0.0 && o.missed_grasps <= 1.0))
    throw Error("demos record: --missed-grasps: expected a share of the episodes from 0 to 1, got " + std::to_string(o.missed_grasps));
  const std::unique_ptr<ScriptedExpert> expert = make_expert(*env);
  auto* manipulation = dynamic_cast<ManipulationExpert*>(expert.get());
  if (o.missed_grasps > 0.0 && !(manipulation && manipulation->grasps()))
    throw Error("demos record: --missed-grasps: expected a task that grasps a cube (pick_and_place, stack), got " +
                env->spec().env_name);
  DemoWriter writer(o.out_path, to_json(env_config), env->spec(), o.append);
  int written = 0, successes = 0;
  const long long max_attempts = o.only_successes ? 10LL * o.episodes : o.episodes;
  for (long long k = 0; k < max_attempts && written < o.episodes; ++k) {
    const std::uint64_t seed = o.seed + static_cast<std::uint64_t>(k);
    DemoEpisode episode;
    episode.source = DemoSource::Scripted;
    episode.seed = seed;
    episode.env_config = to_json(env_config);
    episode.start(env->reset(seed));
    expert->reset();
    if (o.missed_grasps > 0.0) {
      Rng draws = Rng::derive(seed, rng_stream::missed_grasps);
      const bool miss = draws.uniform() < o.missed_grasps;
      // Beside the cube along x, across the fingers (which open along y): open fingers that came
      // down beside it along y would land on it.
      const double side = draws.uniform() < 0.5 ? -1.0 : 1.0;
      const double along = side * draws.uniform(0.045, 0.06), across = draws.uniform(-0.01, 0.01);  // m
      if (miss) manipulation->miss_first_grasp(Eigen::Vector2f(static_cast<float>(along), static_cast<float>(across)));
    }
    Rng noise = Rng::derive(seed, rng_stream::recording_noise);
    while (!episode.ended()) {
      Action a = expert->act();
      if (o.action_noise > 0.0)
        for (Eigen::Index i = 0; i < a.values.size(); ++i)
          a.values[i] = std::clamp(a.values[i] + static_cast<float>(noise.normal(0.0, o.action_noise)), space.low[i], space.high[i]);
      episode.add(a, env->step(a));
    }
    const bool success = episode.success();
    const bool keep = success || !o.only_successes;
    // A line reports an episode only once it is on disk (DemoWriter::append returns after fsync),
    // so a crash or kill -9 never loses an episode reported as written.
    if (keep) writer.append(episode);
    if (!o.quiet) {
      std::printf("episode (seed %llu): %d steps, return %.2f, success %s%s\n", static_cast<unsigned long long>(seed),
                  episode.steps(), episode.episode_return(), success ? "yes" : "no", keep ? "" : " (not written)");
      std::fflush(stdout);
    }
    if (!keep) continue;
    ++written;
    successes += success ? 1 : 0;
  }
  std::printf("wrote %d scripted episodes (success rate %.2f) to %s, which holds %lld\n", written,
              written ? static_cast<double>(successes) / written : 0.0, o.out_path.c_str(), writer.episodes());
  if (written < o.episodes) throw Error("demos record: the expert succeeded in only " + std::to_string(written) + " of " +
                                        std::to_string(max_attempts) + " episodes");
  return 0;
}

Command demos_command_entry() {
  return {"demos", "Demonstration files: what one holds, recording the scripted expert",
          [](CLI::App& cmd) -> std::function<int()> {
            struct Line {
              std::string info_path;
              DemosRecordOptions o;
            };
            auto l = std::make_shared<Line>();
            DemosRecordOptions& o = l->o;
            cmd.require_subcommand(1);
            auto* info = cmd.add_subcommand("info", "Print a demonstration file's env, episodes, steps, success rate and mean return");
            info->add_option("file", l->info_path, "Demonstration file")->required();
            auto* record = cmd.add_subcommand("record", "Record episodes of the scripted expert (privileged state, the env's own actions)");
            record->add_flag("--expert", o.expert,
                             "The scripted expert records (the default and only recorder here; people record with `rdsim teleop --record`)");
            auto* env = record->add_option("--env", o.env, "Env name (its default options, random targets)");
            auto* config = record->add_option("--config", o.config_path, "Or take the \"env\" object of this training config");
            env->excludes(config);
            record->add_option("-n,--episodes", o.episodes, "Episodes to write")->check(CLI::Range(1, 1000000))->capture_default_str();
            record->add_option("--out", o.out_path, "Demonstration file to write")->required();
            record->add_option("--seed", o.seed, "Episode k starts from reset(seed + k)")->capture_default_str();
            record->add_flag("--append", o.append, "Add to an existing file of the same env");
            record->add_flag("--fixed-target", o.fixed_target, "--env: keep the default target (no random_target)");
            record->add_flag("--continuous", o.continuous, "--env: Box(3) actions instead of Discrete(6)");
            record->add_option("--action-noise", o.action_noise,
                               "Box actions: std of the Gaussian noise (action units) added to each expert action before it is "
                               "taken and recorded, so the episodes show the way back to the expert's path (DART)")
                ->check(CLI::Range(0.0, 10.0))->capture_default_str();
            record->add_option("--missed-grasps", o.missed_grasps,
                               "pick_and_place, stack: the share of episodes whose first grasp closes on nothing 4.5-6 cm "
                               "beside the first cube before the expert grasps it (episodes that show the way back)")
                ->check(CLI::Range(0.0, 1.0))->capture_default_str();
            record->add_flag("--only-successes", o.only_successes, "Write successful episodes only");
            record->add_flag("-q,--quiet", o.quiet, "No line per episode");
            return [l, &cmd] {
              if (cmd.get_subcommands().front()->get_name() == "info") return demos_info_command(l->info_path);
              return demos_record_command(l->o);
            };
          }};
}

}  // namespace rdsim
