#include "rdsim/train_config.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "rdsim/error.hpp"
#include "rdsim/files.hpp"

namespace rdsim {
namespace {

constexpr long long max_steps = 1'000'000'000'000LL;

CnnConfig read_cnn(ConfigReader r) {
  CnnConfig c;
  r.read_choice("preset", c.preset, {"auto", "small", "nature"});
  r.read("channels", c.channels, 1, 4096);
  r.read("kernels", c.kernels, 1, 1024);
  r.read("strides", c.strides, 1, 1024);
  r.read("fc", c.fc, 1, 65536);
  if (c.kernels.size() != c.channels.size())
    r.fail("kernels", "expected one kernel size per entry of channels (" + std::to_string(c.channels.size()) + "), got " +
                          std::to_string(c.kernels.size()));
  if (c.strides.size() != c.channels.size())
    r.fail("strides", "expected one stride per entry of channels (" + std::to_string(c.channels.size()) + "), got " +
                          std::to_string(c.strides.size()));
  r.finish();
  return c;
}

nlohmann::json cnn_json(const CnnConfig& c) {
  return {{"preset", c.preset}, {"channels", c.channels}, {"kernels", c.kernels}, {"strides", c.strides}, {"fc", c.fc}};
}

NetworkConfig read_network(ConfigReader r) {
  NetworkConfig c;
  r.read("hidden_sizes", c.hidden_sizes, 1, 65536);
  r.read_choice("activation", c.activation, {"tanh", "relu"});
  r.read("shared", c.shared);
  r.read("log_std_init", c.log_std_init, -20.0, 5.0);
  r.read("input_scale", c.input_scale, 1e-6, 1e6);
  c.cnn = read_cnn(r.child("cnn"));
  r.finish();
  return c;
}

PpoConfig read_ppo(ConfigReader r) {
  PpoConfig c;
  r.read("n_steps", c.n_steps, 1, 1'000'000);
  r.read("batch_size", c.batch_size, 1, 100'000'000);
  r.read("n_epochs", c.n_epochs, 1, 10'000);
  r.read("learning_rate", c.learning_rate, 0.0, 1.0);
  r.read("anneal_lr", c.anneal_lr);
  r.read("adam_eps", c.adam_eps, 0.0, 1.0);
  r.read("gamma", c.gamma, 0.0, 1.0);
  r.read("gae_lambda", c.gae_lambda, 0.0, 1.0);
  r.read("clip_range", c.clip_range, 0.0, 10.0);
  r.read("anneal_clip_range", c.anneal_clip_range);
  r.read("clip_range_vf", c.clip_range_vf, 0.0, 1e9);
  r.read("ent_coef", c.ent_coef, 0.0, 100.0);
  r.read("vf_coef", c.vf_coef, 0.0, 100.0);
  r.read("max_grad_norm", c.max_grad_norm, 1e-9, 1e9);
  r.read("normalize_advantage", c.normalize_advantage);
  r.read("target_kl", c.target_kl, 0.0, 100.0);
  r.finish();
  return c;
}

A2cConfig read_a2c(ConfigReader r) {
  A2cConfig c;
  r.read("n_steps", c.n_steps, 1, 1'000'000);
  r.read("learning_rate", c.learning_rate, 0.0, 1.0);
  r.read("anneal_lr", c.anneal_lr);
  r.read_choice("optimizer", c.optimizer, {"rmsprop", "adam"});
  r.read("rms_alpha", c.rms_alpha, 0.0, 1.0);
  r.read("rms_eps", c.rms_eps, 0.0, 1.0);
  r.read("rms_tf_style", c.rms_tf_style);
  r.read("gamma", c.gamma, 0.0, 1.0);
  r.read("gae_lambda", c.gae_lambda, 0.0, 1.0);
  r.read("ent_coef", c.ent_coef, 0.0, 100.0);
  r.read("vf_coef", c.vf_coef, 0.0, 100.0);
  r.read("max_grad_norm", c.max_grad_norm, 1e-9, 1e9);
  r.read("normalize_advantage", c.normalize_advantage);
  r.finish();
  return c;
}

// ---- DQN: owned by engineer "nn" -------------------------------------------------------------
DqnConfig read_dqn(ConfigReader r) {
  DqnConfig c;
  r.read("learning_rate", c.learning_rate, 0.0, 1.0);
  r.read("anneal_lr", c.anneal_lr);
  r.read("batch_size", c.batch_size, 1, 1'000'000);
  r.read("buffer_size", c.buffer_size, 1, 100'000'000);
  r.read("learning_starts", c.learning_starts, 0, max_steps);
  r.read("gamma", c.gamma, 0.0, 1.0);
  r.read("target_update_interval", c.target_update_interval, 1, max_steps);
  r.read("tau", c.tau, 0.0, 1.0);
  r.read("train_freq", c.train_freq, 1, 1'000'000);
  r.read("gradient_steps", c.gradient_steps, 1, 1'000'000);
  r.read("exploration_fraction", c.exploration_fraction, 0.0, 1.0);
  r.read("exploration_initial_eps", c.exploration_initial_eps, 0.0, 1.0);
  r.read("exploration_final_eps", c.exploration_final_eps, 0.0, 1.0);
  r.read("max_grad_norm", c.max_grad_norm, 1e-9, 1e9);
  r.read("double_q", c.double_q);
  r.read("huber", c.huber);
  r.finish();
  return c;
}

nlohmann::json dqn_json(const DqnConfig& c) {
  return {{"learning_rate", c.learning_rate},
          {"anneal_lr", c.anneal_lr},
          {"batch_size", c.batch_size},
          {"buffer_size", c.buffer_size},
          {"learning_starts", c.learning_starts},
          {"gamma", c.gamma},
          {"target_update_interval", c.target_update_interval},
          {"tau", c.tau},
          {"train_freq", c.train_freq},
          {"gradient_steps", c.gradient_steps},
          {"exploration_fraction", c.exploration_fraction},
          {"exploration_initial_eps", c.exploration_initial_eps},
          {"exploration_final_eps", c.exploration_final_eps},
          {"max_grad_norm", c.max_grad_norm},
          {"double_q", c.double_q},
          {"huber", c.huber}};
}
// ---- end of DQN ------------------------------------------------------------------------------

nlohmann::json ppo_json(const PpoConfig& c) {
  return {{"n_steps", c.n_steps},
          {"batch_size", c.batch_size},
          {"n_epochs", c.n_epochs},
          {"learning_rate", c.learning_rate},
          {"anneal_lr", c.anneal_lr},
          {"adam_eps", c.adam_eps},
          {"gamma", c.gamma},
          {"gae_lambda", c.gae_lambda},
          {"clip_range", c.clip_range},
          {"anneal_clip_range", c.anneal_clip_range},
          {"clip_range_vf", c.clip_range_vf},
          {"ent_coef", c.ent_coef},
          {"vf_coef", c.vf_coef},
          {"max_grad_norm", c.max_grad_norm},
          {"normalize_advantage", c.normalize_advantage},
          {"target_kl", c.target_kl}};
}

nlohmann::json a2c_json(const A2cConfig& c) {
  return {{"n_steps", c.n_steps},
          {"learning_rate", c.learning_rate},
          {"anneal_lr", c.anneal_lr},
          {"optimizer", c.optimizer},
          {"rms_alpha", c.rms_alpha},
          {"rms_eps", c.rms_eps},
          {"rms_tf_style", c.rms_tf_style},
          {"gamma", c.gamma},
          {"gae_lambda", c.gae_lambda},
          {"ent_coef", c.ent_coef},
          {"vf_coef", c.vf_coef},
          {"max_grad_norm", c.max_grad_norm},
          {"normalize_advantage", c.normalize_advantage}};
}

}  // namespace

TrainConfig parse_train_config(const nlohmann::json& json, const std::string& where, const std::string& name) {
  ConfigReader r(json, where);
  TrainConfig c;
  c.source = where;
  c.name = name;
  r.read_choice("algorithm", c.algorithm, {"ppo", "a2c", "dqn"});
  if (!r.has("env")) r.fail("env", "missing: expected an object such as {\"name\": \"cartpole\"}");
  ConfigReader env = r.child("env");
  c.env = read_env_config(env);
  r.read("seed", c.seed);
  r.read("total_timesteps", c.total_timesteps, 1, max_steps);
  r.read("num_envs", c.num_envs, 1, 4096);
  r.read("log_dir", c.log_dir);
  if (c.log_dir.empty()) c.log_dir = "runs/" + name;
  r.read("checkpoint_interval", c.checkpoint_interval, 0, max_steps);
  r.read("stats_window", c.stats_window, 1, 1'000'000);
  c.network = read_network(r.child("network"));
  c.ppo = read_ppo(r.child("ppo"));
  c.a2c = read_a2c(r.child("a2c"));
  c.dqn = read_dqn(r.child("dqn"));
  if (c.network.input_scale != 1.0 && c.env.observation == ObservationMode::RawPixels)
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
  nlohmann::json j = {{"algorithm", c.algorithm},
                      {"env", to_json(c.env)},
                      {"seed", c.seed},
                      {"total_timesteps", c.total_timesteps},
                      {"num_envs", c.num_envs},
                      {"log_dir", c.log_dir},
                      {"checkpoint_interval", c.checkpoint_interval},
                      {"stats_window", c.stats_window},
                      {"network",
                       {{"hidden_sizes", c.network.hidden_sizes},
                        {"activation", c.network.activation},
                        {"shared", c.network.shared},
                        {"log_std_init", c.network.log_std_init},
                        {"input_scale", c.network.input_scale},
                        {"cnn", cnn_json(c.network.cnn)}}}};
  if (c.algorithm == "ppo") j["ppo"] = ppo_json(c.ppo);
  if (c.algorithm == "a2c") j["a2c"] = a2c_json(c.a2c);
  if (c.algorithm == "dqn") j["dqn"] = dqn_json(c.dqn);
  return j;
}

}  // namespace rdsim
