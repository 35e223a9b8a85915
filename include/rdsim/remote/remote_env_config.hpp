#pragma once
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/config_reader.hpp"

// Where an env runs: the keys of a config's "env" object that send it to an `rdsim serve`
// instead of making it in this process:
//   "env": {"name": "jaka_button", "remote": "tcp://host:7777",
//           "server_key": "keys/server.key", "client_key": "keys/alice.key_secret"}
// They are read from the same "env" object as the env's own options (envs/registry.hpp
// read_env_config) but belong to the link, not to the env: the registry's key lists stay the
// env's, a server refuses them in a hello (a session cannot be forwarded again), and the
// resolved config records them only when set. Key entries name key FILES (rdsim keygen), never
// keys.
namespace rdsim {

struct RemoteEnvConfig {
  std::string remote;      // tcp://HOST:PORT of the server; empty: the env runs in this process
  std::string server_key;  // file: the server's public key; empty: plain text (loopback, --insecure servers)
  std::string client_key;  // file: this client's secret key (NAME.key_secret, mode 0600)
  double remote_timeout = 60.0;  // s to wait for each reply

  bool enabled() const { return !remote.empty(); }
};

template <class V, class C>
  requires config::Describes<C, RemoteEnvConfig>
void describe(V& v, C& c) {
  v.field("remote", c.remote, "address of an `rdsim serve` that runs the env (tcp://HOST:PORT); empty = in this process");
  v.field("server_key", c.server_key,
          "file: the server's public key (rdsim keygen); empty = plain text (loopback servers started with --insecure)");
  v.field("client_key", c.client_key, "file: this client's secret key (NAME.key_secret written by rdsim keygen)");
  v.field("remote_timeout", c.remote_timeout, config::Range{0.1, 86400.0}, "s to wait for each reply of the server");
}

// Reads the link keys of an "env" object (only those: read_env_config reads the rest and its
// finish() rejects unknown keys). Checks that the link keys come with "remote", that both key
// files or neither are given, that the address is tcp://HOST:PORT, and that a non-loopback
// server gets keys (plain text is loopback only). rdsim::Error naming the key otherwise. Key file
// paths come back absolute (relative ones are taken from the current folder), so that a run's
// config.json and model files find the keys from any folder.
RemoteEnvConfig read_remote_env_config(ConfigReader& env);

// Adds the link keys to a resolved "env" object when the env is remote.
void write_remote_env_config(const RemoteEnvConfig& config, nlohmann::json& env);

}  // namespace rdsim
