#include "rdsim/remote/remote_env_config.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

#include "rdsim/core/error.hpp"
#include "rdsim/remote/endpoint.hpp"

namespace rdsim {
namespace {

// A key file named relative to the folder rdsim runs in (like every path of a config), as an
// absolute path: the run's config.json and model files record it so, and find it from any folder.
std::string absolute_path(const std::string& path) {
  if (path.empty()) return path;
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

}  // namespace

RemoteEnvConfig read_remote_env_config(ConfigReader& env) {
  RemoteEnvConfig c;
  config::FieldReader reader(env);
  describe(reader, c);
  if (!c.enabled()) {
    for (const char* key : {"server_key", "client_key", "remote_timeout"})
      if (env.has(key)) env.fail(key, "only with \"remote\" (the address of an rdsim serve)");
    return c;
  }
  try {
    remote::check_tcp_endpoint(c.remote, env.name("remote"));
  } catch (const Error& e) {
    throw Error(env.where() + ": " + e.what());
  }
  if (c.server_key.empty() != c.client_key.empty())
    env.fail(c.server_key.empty() ? "server_key" : "client_key",
             "give both server_key (the server's public key file) and client_key (this client's secret key file), or neither");
  if (c.server_key.empty() && !remote::is_loopback_endpoint(c.remote))
    env.fail("server_key", "needed for " + c.remote + ": plain text is allowed only to a loopback address");
  c.server_key = absolute_path(c.server_key);
  c.client_key = absolute_path(c.client_key);
  return c;
}

void write_remote_env_config(const RemoteEnvConfig& config, nlohmann::json& env) {
  if (!config.enabled()) return;
  const nlohmann::json link = config::write_fields(config);
  for (auto it = link.begin(); it != link.end(); ++it) env[it.key()] = it.value();
}

}  // namespace rdsim
