// `rdsim envs`: what can be named in a config's "env.name".
#include "rdsim/app/envs.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/training/train_config.hpp"

namespace rdsim {

namespace {

// A config's env: every option with its value (defaults filled in, paths absolute) and its spaces.
int config_env(const std::string& path) {
  const TrainConfig config = read_train_config(path);
  const Spec spec = config_spec(config);
  std::printf("%s: env %s\n", path.c_str(), config.env.name.c_str());
  std::printf("observation: %s\naction: %s\nsteps per episode: %d\n", describe_observation_space(spec.observation).c_str(),
              describe_action_space(spec.action).c_str(), spec.max_episode_steps);
  if (!spec.observation.parts.empty()) {  // what each value is: name [first, end)
    std::string parts;
    int at = 0;
    for (const ObservationPart& p : spec.observation.parts) {
      parts += (parts.empty() ? "" : ", ") + p.name + " [" + std::to_string(at) + ", " + std::to_string(at + p.size) + ")";
      at += p.size;
    }
    std::printf("observation parts: %s\n", parts.c_str());
  }
  if (spec.goal.active())
    std::printf("goal-conditioned: %s, achieved and desired goals of %d values each, %s reward\n",
                spec.observation.vector_size > 0 ? "the image" : (std::to_string(spec.goal.observation) + " observation values").c_str(),
                spec.goal.goal_size(), to_string(spec.goal.reward));
  std::printf("every option, resolved:\n%s\n", to_json(config.env).dump(2).c_str());
  return 0;
}

}  // namespace

int envs_command(const std::string& config_path) {
  if (!config_path.empty()) return config_env(config_path);
  std::printf("%-16s %-7s %s\n", "name", "pixels", "description");
  for (const auto& e : env_registry()) {
    // pixels: camera images as observations (and frames for people, render_mode).
    const char* pixels = e.supports_pixels ? "yes" : "no";
    std::printf("%-16s %-7s %s\n", e.name.c_str(), pixels, e.description.c_str());
  }
  return 0;
}

Command envs_command_entry() {
  return {"envs", "List the available environments (--config FILE: that config's env, every option resolved)",
          [](CLI::App& cmd) -> std::function<int()> {
            auto path = std::make_shared<std::string>();
            cmd.add_option("--config", *path, "A training config: show its env with every option resolved and its spaces");
            return [path] { return envs_command(*path); };
          }};
}

}  // namespace rdsim
