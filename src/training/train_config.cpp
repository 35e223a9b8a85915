#include "rdsim/training/train_config.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <nlohmann/json.hpp>

#include "rdsim/vecenv/vec_env.hpp"
#include "rdsim/core/config_path.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/json_text.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/nn/gemm.hpp"
#include "rdsim/vecenv/worker_pool.hpp"

namespace rdsim {

namespace {

// Rules that span the env, the algorithm and the run settings; each struct's own rules are in
// its describe(). A key whose value cannot matter is an error, not a silent no-op.
void check_combination(ConfigReader& r, const TrainConfig& c) {
  const bool pixels = c.env.observation == ObservationMode::RawPixels;
  const NetworkConfig defaults;
  ConfigReader network = r.child("network");
  if (pixels) {
    if (c.algorithm.network.input_scale != defaults.input_scale)
      network.fail("input_scale", "only for vector observations (pixels are already scaled to [0, 1]); expected 1");
    const char* mlp_key = c.algorithm.network.hidden_sizes != defaults.hidden_sizes ? "hidden_sizes"
                          : c.algorithm.network.activation != defaults.activation ? "activation"
                          : c.algorithm.network.shared != defaults.shared          ? "shared"
                                                                                   : nullptr;
    if (mlp_key)
      network.fail(mlp_key, "has no effect with raw-pixel observations (the network.cnn trunk is used; remove the key)");
  } else if (config::write_fields(c.algorithm.network.cnn) != config::write_fields(defaults.cnn)) {
    network.fail("cnn", "has no effect with ground-truth observations (only raw_pixels use a CNN; remove the key)");
  }
  if (c.algorithm.normalize_observations) {
    if (pixels)
      r.fail("normalize_observations", "only for vector observations (pixels are already scaled to [0, 1])");
    if (c.algorithm.network.input_scale != defaults.input_scale)
      network.fail("input_scale", "has no effect with normalize_observations (the inputs are standardised; remove the key)");
    // sac, td3 and ddpg start the statistics from the demonstrations (OffPolicy::observe_demonstrations).
    if (c.algorithm.demonstrations && !is_off_policy_actor_critic(c.algorithm.name()))
      r.fail("normalize_observations", "cannot be combined with demonstrations for " + c.algorithm.name() +
                                           " (its pre-training would see other inputs than its training); sac, td3 "
                                           "and ddpg take both");
  }
  if (c.env.is_discrete && c.algorithm.network.log_std_init != defaults.log_std_init)
    network.fail("log_std_init", "has no effect with discrete actions (only Box actions have a Gaussian policy)");

  if (const auto* ppo = std::get_if<PpoConfig>(&c.algorithm.params)) {
    const long long rollout = static_cast<long long>(ppo->n_steps) * c.num_envs;
    if (ppo->batch_size > rollout)
      r.child("ppo").fail("batch_size", "expected at most the rollout size n_steps x num_envs = " + std::to_string(rollout) +
                                            ", got " + std::to_string(ppo->batch_size) +
                                            " (larger minibatches are cut to the rollout)");
  }
  // Off-policy algorithms learn only after learning_starts steps.
  const auto check_learning_starts = [&](const char* algo, long long learning_starts) {
    if (learning_starts >= c.total_timesteps)
      r.child(algo).fail("learning_starts", "expected fewer than total_timesteps (" + std::to_string(c.total_timesteps) +
                                                "), got " + std::to_string(learning_starts) + " (the run would never learn)");
  };
  if (const auto* dqn = std::get_if<DqnConfig>(&c.algorithm.params)) check_learning_starts("dqn", dqn->learning_starts);
  if (const auto* sac = std::get_if<SacConfig>(&c.algorithm.params)) check_learning_starts("sac", sac->learning_starts);
  if (const auto* td3 = std::get_if<Td3Config>(&c.algorithm.params)) check_learning_starts("td3", td3->learning_starts);
  if (const auto* ddpg = std::get_if<DdpgConfig>(&c.algorithm.params)) check_learning_starts("ddpg", ddpg->learning_starts);
}

}  // namespace

TrainConfig parse_train_config(const nlohmann::json& json, const std::string& where, const std::string& name) {
  ConfigReader r(json, where);
  TrainConfig c;
  c.source = where;
  c.name = name;
  c.algorithm = read_algorithm_config(r);
  if (!r.has("env")) r.fail("env", "missing: expected an object such as {\"name\": \"cartpole\"}");
  ConfigReader env = r.child("env");
  c.remote = read_remote_env_config(env);  // first: read_env_config's finish() rejects unread keys
  c.env = read_env_config(env);
  config::FieldReader run(r);
  describe(run, c);
  r.accept("eval");  // known, so that a misspelt key gets "did you mean"
  if (r.has("eval")) {
    ConfigReader section = r.child("eval");
    EvalConfig eval;
    config::read_fields(section, eval);
    c.eval = eval;
  }
  if (c.log_dir.empty() && !name.empty()) c.log_dir = "runs/" + name;  // empty name: the caller picks the folder
  check_combination(r, c);
  r.finish();
  return c;
}

void apply_overrides(nlohmann::json& config, const std::vector<ConfigOverride>& overrides, const std::string& where) {
  for (const ConfigOverride& o : overrides) {
    // The file's own value must be valid too: a bad file stays a bad file whatever replaces the key.
    if (config.is_object() && config.contains(o.key)) {
      nlohmann::json own = nlohmann::json::object();
      own[o.key] = config[o.key];
      ConfigReader reader(own, where);
      TrainConfig scratch;
      config::read_fields(reader, scratch);
    }
    nlohmann::json value = json_from_option(o.text);
    if (value.is_string() && value.get_ref<const std::string&>().empty())
      throw Error(o.option + ": expected a value, got an empty string");
    nlohmann::json alone = nlohmann::json::object();
    alone[o.key] = value;
    ConfigReader reader(alone, o.option);
    TrainConfig scratch;
    config::read_fields(reader, scratch);  // the run settings' types and ranges (describe above)
    if (!config.is_object()) return;        // parse_train_config reports it
    config[o.key] = std::move(value);
  }
}

namespace {

// The paths the config file itself writes, relative to its folder (config_path.hpp): the env's
// (URDF, package paths), the remote env's key files, the demonstration file and log_dir. Values
// given on the command line (`overrides`) stay relative to the current folder.
void resolve_file_paths(TrainConfig& c, const nlohmann::json& file, const std::string& folder,
                        const std::vector<ConfigOverride>& overrides) {
  resolve_env_paths(c.env, folder);
  const auto written = [&](const nlohmann::json& object, const char* key) -> std::string {
    const auto it = object.is_object() ? object.find(key) : object.end();
    return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  const nlohmann::json& env = file.contains("env") ? file["env"] : nlohmann::json();
  if (!written(env, "server_key").empty()) c.remote.server_key = path_from(folder, written(env, "server_key"));
  if (!written(env, "client_key").empty()) c.remote.client_key = path_from(folder, written(env, "client_key"));
  if (c.algorithm.demonstrations && file.contains("demonstrations")) {
    c.algorithm.demonstrations->file = path_from(folder, written(file["demonstrations"], "file"));
    if (!written(file["demonstrations"], "start_file").empty())
      c.algorithm.demonstrations->start_file = path_from(folder, written(file["demonstrations"], "start_file"));
  }
  const bool log_dir_given = std::any_of(overrides.begin(), overrides.end(), [](const ConfigOverride& o) { return o.key == "log_dir"; });
  if (!log_dir_given && !written(file, "log_dir").empty()) c.log_dir = path_from(folder, written(file, "log_dir"));
}

}  // namespace

TrainConfig read_train_config(const std::string& path, const std::vector<ConfigOverride>& overrides) {
  const nlohmann::json file = read_json_file(path);
  nlohmann::json json = file;
  apply_overrides(json, overrides, path);
  TrainConfig c = parse_train_config(json, path, std::filesystem::path(path).stem().string());
  resolve_file_paths(c, file, std::filesystem::path(path).parent_path().string(), overrides);
  return c;
}

Spec config_spec(const TrainConfig& config) {
  try {
    return env_spec(config.env);
  } catch (const Error& e) {
    throw Error(config.source + ": " + e.what());
  }
}

nlohmann::json to_json(const TrainConfig& c) {
  nlohmann::json j = config::write_fields(c);
  j["env"] = to_json(c.env);
  write_remote_env_config(c.remote, j["env"]);
  write_algorithm_config(c.algorithm, j);
  if (c.eval) j["eval"] = config::write_fields(*c.eval);
  return j;
}

int resolve_num_threads(const TrainConfig& c, int local_ranks) {
  int threads = c.num_threads;
  if (threads == 0) {
    const int cores = available_cores();
    // A process that mpirun bound to fewer cores than the machine has uses just those; an unbound
    // one shares the machine's cores with the other ranks on it.
    const int machine = static_cast<int>(std::thread::hardware_concurrency());
    threads = cores < machine ? cores : cores / std::max(local_ranks, 1);
  }
  return std::clamp(threads, 1, c.num_envs);
}

EnvWorkers resolve_env_workers(const TrainConfig& c) {
  if (c.remote.enabled()) {
    if (c.env_workers == "processes")
      throw Error("env_workers: \"processes\" cannot step a remote env (its connection does not survive fork); "
                  "use \"threads\" or \"auto\"");
    return EnvWorkers::threads;
  }
  if (c.env_workers == "auto") return auto_env_workers(c.env);
  const bool draws = c.env.observation == ObservationMode::RawPixels || c.env.render_mode != RenderMode::None;
  if (c.env_workers == "processes" && draws && c.env.renderer != "osmesa")
    throw Error("env_workers: \"processes\" needs \"renderer\": \"osmesa\" (a GPU context does not survive fork); "
                "use \"threads\" or \"auto\"");
  return c.env_workers == "processes" ? EnvWorkers::processes : EnvWorkers::threads;
}

nn::GemmBackend resolve_gemm(TrainConfig& c) {
  const char* variable = std::getenv("RDSIM_GEMM");
  if (variable && *variable) {
    const nn::GemmBackend backend = nn::gemm_backend_from_string(variable, "environment variable RDSIM_GEMM");
    c.gemm = variable;
    return backend;
  }
  return nn::gemm_backend_from_string(c.gemm, (c.source.empty() ? std::string("config") : c.source) + ": gemm");
}

void upgrade_v1_config(nlohmann::json& config) {
  if (!config.is_object() || !config.contains("env") || !config["env"].is_object()) return;
  nlohmann::json& env = config["env"];
  if (!env.contains("name") || !env["name"].is_string()) return;
  const EnvEntry* entry = nullptr;
  for (const auto& e : env_registry())
    if (e.name == env["name"].get<std::string>()) entry = &e;
  if (!entry) return;  // read_env_config names the unknown env
  nlohmann::json upgraded = nlohmann::json::object();
  for (auto it = env.begin(); it != env.end(); ++it) {
    const std::string& key = it.key();
    const bool read = env_reads(*entry, key);
    const bool zero_default = (key == "max_distance" || key == "max_steps" || key == "action_step" ||
                               key == "success_threshold") && it.value().is_number() && it.value().get<double>() == 0.0;
    if (read && !zero_default) upgraded[key] = it.value();
  }
  env = std::move(upgraded);
}

}  // namespace rdsim
