// libFuzzer target: model.bin / checkpoint.bin bytes through the loaders `rdsim replay` and
// `rdsim train --resume` use: the envelope, the embedded config, the spec, the weights and (for
// checkpoints) optimiser, generators, counters, env states and episode tracking.
// CartPole inputs only: the robot envs' loaders are the same code after a 100x slower setup.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string_view>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/training/checkpoint.hpp"
#include "rdsim/training/memory_check.hpp"
#include "rdsim/training/model_file.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const rdsim::ModelFile file = rdsim::decode_model_file(bytes, "fuzz.bin");
    const rdsim::TrainConfig config = rdsim::parse_train_config(file.config, "fuzz.bin", "fuzz");
    if (config.env.name != "cartpole" || config.num_envs > 8) return 0;
    const rdsim::Spec spec = rdsim::env_spec(config.env);
    rdsim::check_memory(rdsim::estimate_training_memory(config, spec), {64e6, "the fuzzer's 64 MB", {}}, "fuzz.bin");
    std::vector<std::unique_ptr<rdsim::Env>> envs;
    for (int i = 0; i < config.num_envs; ++i) envs.push_back(rdsim::make_env(config.env));
    rdsim::VecEnv vec(std::move(envs), config.seed, config.stats_window);
    auto algo = rdsim::make_algorithm(config.algorithm, config.seed, vec.spec());
    rdsim::check_model_spec(file, vec.spec(), "fuzz.bin");
    if (file.kind == rdsim::ModelKind::Model) {
      std::istringstream in(file.payload);
      algo->load(in, false, "fuzz.bin");
    } else {
      (void)rdsim::restore_checkpoint(file.payload, *algo, vec, "fuzz.bin");
    }
  } catch (const rdsim::Error&) {
  }
  return 0;
}
