#pragma once
// Helpers for the remote tests: a scratch folder, key files, and a real server on a free
// loopback port running on its own thread for the length of a test.
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "rdsim/remote/curve_keys.hpp"
#include "rdsim/remote/remote_env_config.hpp"
#include "rdsim/remote/server.hpp"
#include "../scratch_dir.hpp"

namespace rdsim::test {

// A scratch folder named rdsim_remote_<tag>_<pid>.
struct Scratch : ScratchDir {
  explicit Scratch(const std::string& tag) : ScratchDir("remote_" + tag) {}
};

// A server key pair and one authorised client pair, as files in `dir`.
struct TestKeys {
  remote::CurveKeyPair server, client;
  std::string server_public, client_secret;  // the files a client config names
  explicit TestKeys(const Scratch& dir, const std::string& client_name = "alice") {
    server = remote::generate_curve_keys();
    client = remote::generate_curve_keys();
    server_public = remote::write_key_files(dir.path.string(), "server", server)[0];
    client_secret = remote::write_key_files(dir.path.string(), client_name, client)[1];
  }
  RemoteEnvConfig link(const std::string& endpoint) const {
    RemoteEnvConfig c;
    c.remote = endpoint;
    c.server_key = server_public;
    c.client_key = client_secret;
    c.remote_timeout = 30;
    return c;
  }
};

// A Server serving on its own thread; its log lines are kept.
class ServerThread {
public:
  explicit ServerThread(remote::ServerOptions options) : server_(with_log(std::move(options))), thread_([this] { server_.run(); }) {}
  ~ServerThread() {
    server_.stop();
    thread_.join();
  }
  remote::Server& server() { return server_; }
  const std::string& endpoint() const { return server_.endpoint(); }
  std::string log() {
    std::lock_guard<std::mutex> lock(mutex_);
    return log_;
  }

private:
  remote::ServerOptions with_log(remote::ServerOptions o) {
    o.log = [this](const std::string& line) {
      std::lock_guard<std::mutex> lock(mutex_);
      log_ += line + "\n";
    };
    return o;
  }
  std::mutex mutex_;
  std::string log_;
  remote::Server server_;
  std::thread thread_;
};

inline remote::ServerOptions curve_options(const TestKeys& keys) {
  remote::ServerOptions o;
  o.bind = "tcp://127.0.0.1:*";
  o.keys = keys.server;
  o.authorised = {keys.client.public_key};
  return o;
}

inline remote::ServerOptions plain_options() {
  remote::ServerOptions o;
  o.bind = "tcp://127.0.0.1:*";
  o.insecure = true;
  return o;
}

// Polls `done` every 10 ms for up to `seconds`.
template <class F>
bool eventually(F&& done, double seconds = 5.0) {
  for (int i = 0; i < static_cast<int>(seconds * 100); ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

}  // namespace rdsim::test
