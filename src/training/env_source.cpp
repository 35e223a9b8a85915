#include "rdsim/training/env_source.hpp"

#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/remote_env.hpp"

namespace rdsim {

std::unique_ptr<Env> open_env(const EnvConfig& env, const RemoteEnvConfig& remote) {
  if (remote.enabled()) return connect_remote_env(remote, env);
  return make_env(env);
}

std::vector<std::unique_ptr<Env>> open_envs(TrainConfig& config) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < config.num_envs; ++i) envs.push_back(open_env(config.env, config.remote));
  if (const auto* remote = dynamic_cast<const RemoteEnv*>(envs.front().get())) config.env = remote->resolved_config();
  return envs;
}

}  // namespace rdsim
