// `rdsim render`: what the agent of a raw-pixel env sees after reset, as a PNG file.
#include "rdsim/app/render.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <vector>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/render/png.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {

namespace {

// The env to draw: --env's defaults, or a config's "env" object (its paths from its folder).
EnvConfig env_to_draw(const RenderOptions& o) {
  if (o.env.empty() == o.config_path.empty()) throw Error("render: give --env NAME or --config FILE");
  EnvConfig config = o.config_path.empty() ? default_env_config(o.env) : read_train_config(o.config_path).env;
  if (auto* reach = config.find<ReachOptions>(); reach && (o.random_target || o.config_path.empty()))
    reach->random_target = o.random_target;
  return config;
}

}  // namespace

int render_command(const RenderOptions& o) {
  if (o.view != 1 && o.view != 2) throw Error("render: --view must be 1 or 2, got " + std::to_string(o.view));
  if (!o.env.empty()) env_entry(o.env);  // rdsim::Error listing the names when unknown
  EnvConfig config = env_to_draw(o);
  const EnvEntry& entry = env_entry(config.name);
  if (!entry.supports_pixels)
    throw Error("render: env \"" + config.name + "\" has no camera to draw pixels with (see `rdsim envs`)");
  config.observation = ObservationMode::RawPixels;
  config.multi_view = o.view == 2;
  config.image_width = o.width;
  config.image_height = o.height;
  const std::unique_ptr<Env> env = make_env(config);
  const ObservationSpace& space = env->spec().observation;
  const Observation obs = env->reset(o.seed);
  const int channels = 3 * o.view;
  if (space.type != ObsType::UInt8 || space.shape.size() != 3 || space.shape[2] != channels ||
      obs.pixels.size() != static_cast<size_t>(space.size()))
    throw Error("render: env \"" + config.name + "\" did not return " + std::to_string(channels) + "-channel pixels");
  const int h = space.shape[0], w = space.shape[1];
  // View 2 is channels 3..5 of each pixel of the stacked observation.
  std::vector<std::uint8_t> rgb(static_cast<size_t>(w) * static_cast<size_t>(h) * 3);
  const size_t first = static_cast<size_t>(channels - 3);
  for (size_t p = 0; p < rgb.size() / 3; ++p)
    for (size_t c = 0; c < 3; ++c) rgb[3 * p + c] = obs.pixels[p * static_cast<size_t>(channels) + first + c];
  write_png(o.out_path, w, h, 3, rgb.data());
  std::printf("wrote %s (%s, %dx%d, view %d, seed %llu)\n", o.out_path.c_str(), config.name.c_str(), w, h, o.view,
              static_cast<unsigned long long>(o.seed));
  return 0;
}

Command render_command_entry() {
  return {"render", "Write the raw-pixel observation an env gives after reset as a PNG",
          [](CLI::App& cmd) -> std::function<int()> {
            struct Line {
              RenderOptions o;
              std::string seed;
            };
            auto l = std::make_shared<Line>();
            RenderOptions& o = l->o;
            auto* env = cmd.add_option("--env", o.env, "Env name (see `rdsim envs`; needs pixels): its defaults");
            cmd.add_option("--config", o.config_path, "Or the \"env\" object of this training config (your robot, its options)")
                ->excludes(env);
            cmd.add_option("--out", o.out_path, "PNG file to write")->required();
            cmd.add_option("--view", o.view, "Camera: 1 = main, 2 = second (multi-view) camera")->check(CLI::IsMember({1, 2}))->capture_default_str();
            cmd.add_option("--width", o.width, "Image width in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
            cmd.add_option("--height", o.height, "Image height in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
            cmd.add_option("--seed", l->seed, "Reset seed (default 0)")->type_name("INT");
            cmd.add_flag("--random-target", o.random_target, "Randomise the target at reset (env.random_target)");
            return [l, &cmd] {
              if (cmd.count("--seed")) l->o.seed = seed_from_option(l->seed, "--seed");
              return render_command(l->o);
            };
          }};
}

}  // namespace rdsim
