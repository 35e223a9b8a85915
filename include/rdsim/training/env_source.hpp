#pragma once
#include <memory>
#include <vector>

#include "rdsim/training/train_config.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/demos/demo_file.hpp"

// Where the app's envs come from: made in this process (envs/registry.hpp make_env) or, when the
// config's "env" names a server ("remote": "tcp://..."), sessions of an `rdsim serve`
// (remote/remote_env.hpp), which the rest of rdsim drives through the same Env interface.
namespace rdsim {

std::unique_ptr<Env> open_env(const EnvConfig& env, const RemoteEnvConfig& remote);

// The config.num_envs envs of a run. For remote envs, config.env becomes the env config the
// server resolved, so config.json and model.bin record the values the env really uses. With
// demonstrations.start_fraction, each env starts that share of its episodes from states of `demos`
// (the config's demonstrations, or its start_file's; demonstration_starts.hpp).
std::vector<std::unique_ptr<Env>> open_envs(TrainConfig& config, const std::shared_ptr<const DemoFile>& demos = nullptr);

}  // namespace rdsim
