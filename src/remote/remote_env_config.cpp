#include "rdsim/remote/remote_env_config.hpp"

#include <nlohmann/json.hpp>

#include "rdsim/core/config_path.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/remote/endpoint.hpp"

namespace rdsim {
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
  c.server_key = path_from("", c.server_key);
  c.client_key = path_from("", c.client_key);
  return c;
}

void write_remote_env_config(const RemoteEnvConfig& config, nlohmann::json& env) {
  if (!config.enabled()) return;
  const nlohmann::json link = config::write_fields(config);
  for (auto it = link.begin(); it != link.end(); ++it) env[it.key()] = it.value();
}

}  // namespace rdsim
