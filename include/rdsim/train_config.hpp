#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "rdsim/env_config.hpp"

// The typed form of a training config (configs/*.json), read ONCE by read_train_config; nothing
// downstream looks at JSON. Defaults below are the documented defaults of every key; the
// resolved config (all defaults filled in) is written to <log_dir>/config.json and embedded in
// model.bin, so a model file alone rebuilds its env and policy.
namespace rdsim {

// "network.cnn": the convolutional trunk used when the env observes pixels (UInt8 images).
// "preset": "auto" (default) = "small" below 84x84, "nature" at 84x84 and above;
//   "small"  = 16 8x8/4, 32 4x4/2, fc 256   (Mnih et al. 2013; 64x64 -> 6x6x32 features);
//   "nature" = 32 8x8/4, 64 4x4/2, 64 3x3/1, fc 512 (Mnih et al. 2015).
// "channels", "kernels", "strides" (same length, no padding) replace the preset's conv stack and
// "fc" its dense layers (at least one) when given. Convs and fc use ReLU; with pixels the
// actor and critic always share the CNN (policy and value are linear heads on its features)
// and hidden_sizes/activation/shared are not used.
struct CnnConfig {
  std::string preset = "auto";
  std::vector<int> channels, kernels, strides;  // empty = the preset's
  std::vector<int> fc;                          // empty = the preset's
};

struct NetworkConfig {
  std::vector<int> hidden_sizes = {64, 64};  // "hidden_sizes"
  std::string activation = "tanh";           // "activation": "tanh" | "relu"
  bool shared = false;        // "shared": actor and critic share the hidden layers (one trunk)
  double log_std_init = 0.0;  // "log_std_init": initial log std of Gaussian (Box) policies
  // "input_scale": vector observations (any algorithm): the networks see every observation value
  // times this. Reaching tasks observe metres, where a few centimetres decide between a clear pass
  // and a collision; 10 (decimetres) brings such inputs near unit scale, so a tanh network draws
  // sharp boundaries without first growing large first-layer weights. One factor for all inputs
  // keeps distances isotropic (per-input running standardisation did worse on jaka_obstacle: README).
  double input_scale = 1.0;
  CnnConfig cnn;              // "cnn": pixel observations only (see CnnConfig)
};

// Proximal Policy Optimisation (clipped surrogate). Defaults: Stable-Baselines3's.
struct PpoConfig {
  int n_steps = 2048;              // env steps per env per update
  int batch_size = 64;             // minibatch size (samples)
  int n_epochs = 10;               // passes over each rollout
  double learning_rate = 3e-4;     // Adam
  bool anneal_lr = false;          // linear decay to 0 over total_timesteps
  double adam_eps = 1e-5;
  double gamma = 0.99;
  double gae_lambda = 0.95;
  double clip_range = 0.2;         // policy ratio clip
  bool anneal_clip_range = false;  // linear decay of clip_range to 0
  double clip_range_vf = 0.0;      // value clip around the old value; 0 = no value clipping
  double ent_coef = 0.0;
  double vf_coef = 0.5;
  double max_grad_norm = 0.5;      // global gradient-norm clip
  bool normalize_advantage = true; // per minibatch
  double target_kl = 0.0;          // stop the epochs early above 1.5 * target_kl; 0 = never
};

// Advantage Actor-Critic (synchronous). Defaults: Stable-Baselines3's (RMSprop like baselines).
struct A2cConfig {
  int n_steps = 5;
  double learning_rate = 7e-4;
  bool anneal_lr = false;
  std::string optimizer = "rmsprop";  // "rmsprop" | "adam"
  double rms_alpha = 0.99;
  double rms_eps = 1e-5;
  bool rms_tf_style = false;          // eps inside the sqrt, square average starting at 1
  double gamma = 0.99;
  double gae_lambda = 1.0;            // 1 = plain n-step returns
  double ent_coef = 0.0;
  double vf_coef = 0.5;
  double max_grad_norm = 0.5;
  bool normalize_advantage = false;
};

// ---- DQN: owned by engineer "nn" (algorithms/dqn.cpp); fields and defaults are theirs to adjust.
struct DqnConfig {
  double learning_rate = 1e-4;
  bool anneal_lr = false;
  int batch_size = 32;
  long long buffer_size = 1000000;
  long long learning_starts = 100;
  double gamma = 0.99;
  long long target_update_interval = 10000;  // env steps between target-network updates
  double tau = 1.0;                          // 1 = hard copy, < 1 = Polyak
  int train_freq = 4;                        // env steps per env between training phases
  int gradient_steps = 1;                    // gradient steps per training phase
  double exploration_fraction = 0.1;
  double exploration_initial_eps = 1.0;
  double exploration_final_eps = 0.05;
  double max_grad_norm = 10.0;
  bool double_q = false;
  bool huber = true;                         // Huber (smooth L1) TD loss, else squared error
};
// ---- end of DQN

struct TrainConfig {
  std::string source;                 // the file it was read from (for messages)
  std::string name;                   // the file's stem: "cartpole_ppo"
  std::string algorithm = "ppo";      // "ppo" | "a2c" | "dqn"
  EnvConfig env;                      // "env" (read_env_config)
  std::uint64_t seed = 0;
  long long total_timesteps = 100000;
  int num_envs = 1;
  std::string log_dir;                // default "runs/<name>"
  long long checkpoint_interval = 0;  // env steps between checkpoint.bin writes; 0 = at the end only
  int stats_window = 20;              // episodes behind progress.csv's return/length/success columns
  NetworkConfig network;
  PpoConfig ppo;
  A2cConfig a2c;
  DqnConfig dqn;
};

// Reads and validates a config file. Unknown keys, wrong types, out-of-range values, a missing
// file or bad JSON throw rdsim::Error naming the file and the key.
TrainConfig read_train_config(const std::string& path);

// The same from parsed JSON; `where` names the source in messages, `name` becomes TrainConfig::name.
TrainConfig parse_train_config(const nlohmann::json& json, const std::string& where, const std::string& name);

// The resolved config: every key with its value, defaults filled in. Only the section of the
// chosen algorithm is included. parse_train_config(to_json(c)) == c.
nlohmann::json to_json(const TrainConfig& config);

}  // namespace rdsim
