#include "rdsim/training/env_source.hpp"

#include <string>

#include "rdsim/core/assert.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/scene_redraw.hpp"
#include "rdsim/demos/demo_fit.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/remote_env.hpp"
#include "rdsim/training/demonstration_starts.hpp"

namespace rdsim {

std::unique_ptr<Env> open_env(const EnvConfig& env, const RemoteEnvConfig& remote) {
  if (remote.enabled()) return connect_remote_env(remote, env);
  return make_env(env);
}

std::vector<std::unique_ptr<Env>> open_envs(TrainConfig& config, const std::shared_ptr<const DemoFile>& demos) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < config.num_envs; ++i) envs.push_back(open_env(config.env, config.remote));
  if (const auto* remote = dynamic_cast<const RemoteEnv*>(envs.front().get())) config.env = remote->resolved_config();
  const auto& dc = config.algorithm.demonstrations;
  if (!dc || dc->start_fraction <= 0.0) return envs;
  RDSIM_ASSERT(demos != nullptr, "the demonstrations are read before the envs that start from them");
  const bool own_file = !dc->start_file.empty();
  try {
    check_demos_fit(*demos, to_json(config.env), envs.front()->spec());  // before any replay
  } catch (const Error& e) {
    throw Error(config.source + (own_file ? ": demonstrations.start_file: " : ": demonstrations.file: ") + e.what());
  }
  const std::string where = config.source + (own_file ? ": demonstrations.start_file" : ": demonstrations.start_fraction");
  if (dc->start_redraw > 0.0 && !dynamic_cast<const SceneRedraw*>(envs.front().get()))
    throw Error(config.source + ": demonstrations.start_redraw: " + config.env.name +
                " cannot draw its layout again mid-episode (the manipulation tasks can, run here without per-step "
                "randomization); expected 0");
  for (auto& env : envs) env = start_from_demonstrations(std::move(env), demos, dc->start_fraction, where, dc->start_redraw);
  return envs;
}

}  // namespace rdsim
