#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/algorithms/algorithm_config.hpp"
#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/remote/remote_env_config.hpp"
#include "rdsim/training/eval_config.hpp"

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
  RemoteEnvConfig remote;  // the "env" object's link keys: where the env runs (training/env_source.hpp)
  AlgorithmConfig algorithm;
  // The run's settings (describe() below):
  std::uint64_t seed = 0;
  long long total_timesteps = 100000;
  int num_envs = 1;
  std::string log_dir;  // empty: runs/<name>
  long long checkpoint_interval = 0;
  double checkpoint_seconds = 60.0;
  int stats_window = 100;  // episodes: the convention of SB3 and of the docs' figures
  int num_threads = 0;  // 0: resolved by resolve_num_threads()
  std::string env_workers = "auto";  // resolved by resolve_env_workers()
  int env_groups = 1;
  std::string gemm = "eigen";        // the learner's arithmetic (nn/gemm.hpp); RDSIM_GEMM overrides
  int sync_check_interval = 10;
  std::optional<EvalConfig> eval;  // the "eval" object (eval_config.hpp); none: no evaluation
};

inline constexpr long long max_timesteps = 1'000'000'000'000LL;

template <class V, class C>
  requires config::Describes<C, TrainConfig>
void describe(V& v, C& c) {
  v.field("seed", c.seed, "seed of every random stream (envs, network init, sampling)");
  v.field("total_timesteps", c.total_timesteps, config::Range{1LL, max_timesteps}, "env steps to train, all envs together; the run ends after the update that reaches it (rounded up to whole "
          "updates: rollouts of n_steps x num_envs, one step of every env, or whole episodes)");
  v.field("num_envs", c.num_envs, config::Range{1, 4096}, "envs stepped in lockstep (VecEnv)");
  v.field("log_dir", c.log_dir, "run folder; empty = runs/<config file stem>");
  v.field("checkpoint_interval", c.checkpoint_interval, config::Range{0LL, max_timesteps},
          "env steps between checkpoints (checkpoint.bin and model.bin); 0 = by time only");
  v.field("checkpoint_seconds", c.checkpoint_seconds, config::Range{0.0, 1e6},
          "wall-clock seconds between checkpoints, so a killed run loses at most about this much; 0 = by steps only");
  v.field("stats_window", c.stats_window, config::Range{1, 1'000'000},
          "episodes behind progress.csv's return/length/success columns");
  v.field("num_threads", c.num_threads, config::Range{0, 4096},
          "workers stepping the envs (threads, or processes: env_workers; results do not depend on it); "
          "0 = every core this process may use "
          "(shared among the MPI ranks on one machine), at most num_envs");
  v.field("env_groups", c.env_groups, config::Range{1, 4096},
          "on-policy rollouts (PPO, A2C, TRPO): the envs cut into this many groups, stepped in turn: while the policy "
          "acts on one group the workers step the others, so no worker waits for the other's last env at every step "
          "(asynchronous batches in a fixed order; they overlap for envs any thread may step, the reach tasks without "
          "pixels). Every env gets its actions as with 1, but the policy acts on smaller batches, whose last bits may "
          "round differently: a seed's CSVs depend on env_groups, not on num_threads. At most num_envs");
  v.choice("env_workers", c.env_workers, {"auto", "threads", "processes"},
           "what the num_threads workers are: threads, or processes (this one and num_threads - 1 children, "
           "each stepping its share of the envs; for pixel envs, whose drawing Mesa serialises within a "
           "process); auto = processes for pixel observations drawn by osmesa, threads otherwise and for a remote env. "
           "Results do not depend on it");
  v.choice("gemm", c.gemm, {"eigen", "onednn"},
           "the networks' matrix products and convolutions: eigen (Eigen's products, on one thread) or onednn (oneDNN's "
           "kernels, in builds with libdnnl-dev: faster, and during updates on num_threads threads with the same "
           "results on any count). The two round differently, so a seed's CSVs differ between them. The "
           "environment variable RDSIM_GEMM overrides it");
  v.field("sync_check_interval", c.sync_check_interval, config::Range{0, 1'000'000},
          "MPI runs: updates between comparisons of a hash of the weights across ranks; 0 = at the end only");
}

// The thread count a run uses: `num_threads`, or for 0 the cores this process may use
// (available_cores) divided among `local_ranks` processes of one MPI job on this machine; at
// least 1, at most num_envs.
int resolve_num_threads(const TrainConfig& config, int local_ranks);

enum class EnvWorkers;  // rdsim/vecenv/vec_env.hpp

// The run's `env_workers`: "auto" is auto_env_workers(config.env), and threads for a remote env
// (its connection does not survive fork); rdsim::Error for "processes" with a remote env.
EnvWorkers resolve_env_workers(const TrainConfig& config);

namespace nn {
enum class GemmBackend;  // rdsim/nn/gemm.hpp
}

// The run's learner arithmetic: the environment variable RDSIM_GEMM where set (written into
// config.gemm, so that the run's config.json records it), else config.gemm. rdsim::Error for
// "onednn" in a build without oneDNN, naming the config key or the variable.
nn::GemmBackend resolve_gemm(TrainConfig& config);

// A run setting given on the command line instead of the config file ("--seed 4" sets "seed").
// It is read with the config file's rules (type, range; read_train_config) and errors name the
// option: "--seed: seed: expected an integer in [0, 2^64 - 1], got -1".
struct ConfigOverride {
  std::string option;  // "--seed"
  std::string key;     // "seed": a top-level key of the config
  std::string text;    // as typed: a number where the key wants one, else the string itself
};

// Puts the overrides into a config's JSON, each first checked on its own (naming its option); the
// value it replaces is checked too (naming `where`, the config's source).
void apply_overrides(nlohmann::json& config, const std::vector<ConfigOverride>& overrides, const std::string& where);

// Reads and validates a config file (bounded: core/json_text.hpp), with `overrides` applied
// before validation. Unknown keys, wrong types, out-of-range values, keys without effect,
// contradicting keys, a missing file or bad JSON throw rdsim::Error naming the file and the key.
TrainConfig read_train_config(const std::string& path, const std::vector<ConfigOverride>& overrides = {});

// The same from parsed JSON; `where` names the source in messages, `name` becomes TrainConfig::name
// and, when not empty, names the default log_dir (runs/NAME; empty: the caller sets log_dir).
TrainConfig parse_train_config(const nlohmann::json& json, const std::string& where, const std::string& name);

// The Spec of the config's envs (envs/registry.hpp env_spec: no renderer is built). An env that
// refuses the config (a value only the env can judge, a URDF it cannot load) is an rdsim::Error
// naming config.source too.
Spec config_spec(const TrainConfig& config);

// The resolved config: every key with its value, defaults filled in (the env's keys, the chosen
// algorithm's object). parse_train_config(to_json(c)) == c.
nlohmann::json to_json(const TrainConfig& config);

// A config embedded by model format version 1 (before env defaults were published) recorded the
// env's task numbers as 0 ("the env's default") and every env key whether the env read it or not:
// this turns it into today's form (drops those zeros and the keys the env does not read), so old
// model and checkpoint files still load and replay the same physics.
void upgrade_v1_config(nlohmann::json& config);

}  // namespace rdsim
