#include "rdsim/app/train_config.hpp"

#include <algorithm>
#include <filesystem>
#include <thread>
#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/parallel/worker_pool.hpp"

namespace rdsim {

TrainConfig parse_train_config(const nlohmann::json& json, const std::string& where, const std::string& name) {
  ConfigReader r(json, where);
  TrainConfig c;
  c.source = where;
  c.name = name;
  c.algorithm = read_algorithm_config(r);
  if (!r.has("env")) r.fail("env", "missing: expected an object such as {\"name\": \"cartpole\"}");
  ConfigReader env = r.child("env");
  c.env = read_env_config(env);
  config::FieldReader run(r);
  describe(run, c);
  if (c.log_dir.empty()) c.log_dir = "runs/" + name;
  if (c.algorithm.network.input_scale != 1.0 && c.env.observation == ObservationMode::RawPixels)
    r.child("network").fail("input_scale", "only for vector observations (pixels are already scaled to [0, 1]); expected 1");
  r.finish();
  return c;
}

TrainConfig read_train_config(const std::string& path) {
  const std::string text = read_file(path);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.what() reads "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    std::string what = e.what();
    const auto at = what.find("parse error");
    throw Error(path + ": not valid JSON: " + (at == std::string::npos ? what : what.substr(at)));
  }
  return parse_train_config(json, path, std::filesystem::path(path).stem().string());
}

nlohmann::json to_json(const TrainConfig& c) {
  nlohmann::json j = config::write_fields(c);
  j["env"] = to_json(c.env);
  write_algorithm_config(c.algorithm, j);
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
    const bool read = key == "name" || std::find(entry->keys.begin(), entry->keys.end(), key) != entry->keys.end();
    const bool zero_default = (key == "max_distance" || key == "max_steps" || key == "action_step" ||
                               key == "success_threshold") && it.value().is_number() && it.value().get<double>() == 0.0;
    if (read && !zero_default) upgraded[key] = it.value();
  }
  env = std::move(upgraded);
}

}  // namespace rdsim
