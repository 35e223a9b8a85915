#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/env_config.hpp"

// The typed form of a training config (configs/*.json), read ONCE by read_train_config; nothing
// downstream looks at JSON. It composes the env's options (EnvConfig, read over the env's own
// defaults), the learner's (AlgorithmConfig: "algorithm", "network" and the algorithm's object)
// and the run's own settings below. The resolved config (every value filled in) is written to
// <log_dir>/config.json and embedded in model.bin, so a model file alone rebuilds its env and policy.
namespace rdsim {

struct TrainConfig {
  std::string source;  // the file it was read from (for messages)
  std::string name;    // the file's stem: "cartpole_ppo"
  EnvConfig env;
  AlgorithmConfig algorithm;
  // The run's settings (describe() below):
  std::uint64_t seed = 0;
  long long total_timesteps = 100000;
  int num_envs = 1;
  std::string log_dir;  // empty: runs/<name>
  long long checkpoint_interval = 0;
  int stats_window = 20;
  int num_threads = 0;  // 0: resolved by resolve_num_threads()
  int sync_check_interval = 10;
};

inline constexpr long long max_timesteps = 1'000'000'000'000LL;

template <class V, class C>
  requires config::Describes<C, TrainConfig>
void describe(V& v, C& c) {
  v.field("seed", c.seed, "seed of every random stream (envs, network init, sampling)");
  v.field("total_timesteps", c.total_timesteps, config::Range{1LL, max_timesteps}, "env steps to train, all envs together");
  v.field("num_envs", c.num_envs, config::Range{1, 4096}, "envs stepped in lockstep (VecEnv)");
  v.field("log_dir", c.log_dir, "run folder; empty = runs/<config file stem>");
  v.field("checkpoint_interval", c.checkpoint_interval, config::Range{0LL, max_timesteps},
          "env steps between checkpoint.bin writes; 0 = at the end only");
  v.field("stats_window", c.stats_window, config::Range{1, 1'000'000},
          "episodes behind progress.csv's return/length/success columns");
  v.field("num_threads", c.num_threads, config::Range{0, 4096},
          "threads stepping the envs (results do not depend on it); 0 = every core this process may use "
          "(shared among the MPI ranks on one machine), at most num_envs");
  v.field("sync_check_interval", c.sync_check_interval, config::Range{0, 1'000'000},
          "MPI runs: updates between comparisons of a hash of the weights across ranks; 0 = at the end only");
}

// The thread count a run uses: `num_threads`, or for 0 the cores this process may use
// (available_cores) divided among `local_ranks` processes of one MPI job on this machine; at
// least 1, at most num_envs.
int resolve_num_threads(const TrainConfig& config, int local_ranks);

// Reads and validates a config file. Unknown keys, wrong types, out-of-range values, a missing
// file or bad JSON throw rdsim::Error naming the file and the key.
TrainConfig read_train_config(const std::string& path);

// The same from parsed JSON; `where` names the source in messages, `name` becomes TrainConfig::name.
TrainConfig parse_train_config(const nlohmann::json& json, const std::string& where, const std::string& name);

// The resolved config: every key with its value, defaults filled in (the env's keys, the chosen
// algorithm's object). parse_train_config(to_json(c)) == c.
nlohmann::json to_json(const TrainConfig& config);

// A config embedded by model format version 1 (before env defaults were published) recorded the
// env's task numbers as 0 ("the env's default") and every env key whether the env read it or not:
// this turns it into today's form (drops those zeros and the keys the env does not read), so old
// model and checkpoint files still load and replay the same physics.
void upgrade_v1_config(nlohmann::json& config);

}  // namespace rdsim
