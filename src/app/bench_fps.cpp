// `rdsim bench-fps`: the command line of the env steps/s benchmark (rdsim/bench/bench_fps.hpp).
#include <CLI/CLI.hpp>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/bench/bench_fps.hpp"
#include "rdsim/core/env_config.hpp"

namespace rdsim {

Command bench_fps_command_entry() {
  return {"bench-fps", "Measure env steps per second (random actions, resets included; median of several runs): "
          "one env on one thread, or a VecEnv on several (--threads, --scaling)",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<BenchFpsOptions>();
            cmd.add_option("--env", o->envs, "Env to measure (repeatable; default: all)");
            cmd.add_option("--mode", o->modes, "Observation mode: ground_truth or raw_pixels (repeatable)")
                ->check(CLI::IsMember({"ground_truth", "raw_pixels"}));
            cmd.add_option("--image-size", o->image_sizes,
                           "Raw-pixel image side in pixels, one row each (repeatable; default: 64 and 224)")
                ->check(CLI::Range(1, 4096));
            cmd.add_option("--image-channels", o->image_channels,
                           "Raw-pixel image channels (env image_channels: rgb, rgb_depth_segmentation, ...), one row each "
                           "(repeatable; default: rgb)")
                ->check(CLI::IsMember(image_channel_names()));
            cmd.add_option("--runs", o->runs, "Runs per row; the median is reported")->check(CLI::Range(1, 1000))->capture_default_str();
            cmd.add_option("--steps", o->steps, "Env steps per run")->check(CLI::Range(1LL, 1'000'000'000LL))->capture_default_str();
            cmd.add_option("--threads", o->threads,
                           "Threaded mode: a VecEnv of --num-envs envs on 1 and N threads; steps/s, speed-up, pool overhead")
                ->check(CLI::Range(1, 4096));
            cmd.add_flag("--scaling", o->scaling, "Threaded mode on 1, 2, 4, ... threads up to every core");
            cmd.add_option("--num-envs", o->num_envs, "Threaded mode: envs in the VecEnv (default: 4 per thread of the largest count)")
                ->check(CLI::Range(1, 4096));
            cmd.add_flag("--paper", o->paper,
                         "Like-for-like Table 3: each robot env's paper preset (configs/paper/, the original's per-step "
                         "work) next to its defaults, ground truth and 224x224 pixels");
            cmd.add_option("--set", o->settings,
                           "KEY=VALUE: an env key for every measured env (repeatable), as in a config's env object, e.g. "
                           "--env push --set substeps=5 --set physics_step=0.008")
                ->type_name("KEY=VALUE");
            add_json_option(cmd, o->json_path);
            return [o, &cmd] {
              resolve_json_option(cmd, o->json_path);
              return bench_fps_command(*o);
            };
          }};
}

}  // namespace rdsim
