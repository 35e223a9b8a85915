// `rdsim serve`: hosts environments for remote clients until SIGINT/SIGTERM.
#include "rdsim/app/serve.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/remote/curve_keys.hpp"
#include "rdsim/remote/server.hpp"

namespace rdsim {
namespace {

// SIGINT and SIGTERM are blocked in every thread from the start (the server's threads inherit
// the mask), so no system call is ever interrupted by them and one arriving at any moment, even
// before the socket is bound, stays pending until this thread takes it and stops the server.
class StopSignals {
public:
  StopSignals() {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set_, nullptr);
  }
  // Stops `server` on the first signal, until the object goes.
  void watch(remote::Server& server) {
    thread_ = std::thread([this, &server] {
      const timespec tick{0, 100 * 1000 * 1000};  // 100 ms: how soon the watcher notices done_
      while (!done_.load())
        if (sigtimedwait(&set_, nullptr, &tick) > 0) {
          server.stop();
          return;
        }
    });
  }
  // Stops watching (before the server goes).
  void end() {
    done_.store(true);
    if (thread_.joinable()) thread_.join();
  }
  ~StopSignals() { end(); }

private:
  sigset_t set_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// DIR/server.key_secret and the keys in DIR/clients/.
void load_keys(const std::string& dir, remote::ServerOptions& o) {
  namespace fs = std::filesystem;
  o.keys = remote::read_secret_key((fs::path(dir) / "server.key_secret").string());
  const fs::path clients = fs::path(dir) / "clients";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(clients, ec))
    if (entry.is_regular_file() && entry.path().extension() == ".key")
    {
      o.authorised.push_back(remote::read_public_key(entry.path().string()));
      o.key_names[o.authorised.back()] = entry.path().filename().string();  // the log names clients so
    }
  if (o.authorised.empty())
    throw Error(clients.string() + ": no client public keys (*.key) in it: copy there the NAME.key of each client "
                                   "allowed in (rdsim keygen NAME)");
}

}  // namespace

int serve_command(const ServeOptions& options) {
  StopSignals signals;  // first: a signal during start-up must not kill the process
  remote::ServerOptions o;
  o.bind = options.bind;
  o.insecure = options.insecure;
  o.max_sessions = options.max_sessions;
  o.idle_timeout = options.idle_timeout;
  if (!options.keys_dir.empty()) {
    if (options.insecure) throw Error("serve: --keys and --insecure exclude each other");
    load_keys(options.keys_dir, o);
  }
  const std::size_t clients = o.authorised.size();
  remote::Server server(std::move(o));
  if (options.keys_dir.empty())
    std::fprintf(stderr, "rdsim serve: WARNING: --insecure: plain text, no authentication and no encryption "
                         "(allowed on loopback addresses only)\n");
  std::printf("rdsim serve: listening on %s (%s, at most %d sessions, idle timeout %g s)\n", server.endpoint().c_str(),
              options.keys_dir.empty() ? "plain text"
                                       : ("CurveZMQ, " + std::to_string(clients) + " authorised client key" +
                                          (clients == 1 ? "" : "s")).c_str(),
              options.max_sessions, options.idle_timeout);
  std::fflush(stdout);
  signals.watch(server);
  server.run();
  signals.end();
  const remote::ServerStats s = server.stats();
  std::fprintf(stderr, "rdsim serve: stopped after %lld requests (%lld errors), %lld sessions, %lld refused connections\n",
               s.requests, s.errors, s.sessions_opened, s.refused);
  // What the errors were, most frequent first.
  std::vector<std::pair<long long, std::string>> kinds;
  for (const auto& [message, n] : s.error_kinds) kinds.emplace_back(n, message);
  std::stable_sort(kinds.begin(), kinds.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [n, message] : kinds) std::fprintf(stderr, "rdsim serve:   %lld x %s\n", n, message.c_str());
  return 0;
}

Command serve_command_entry() {
  return {"serve", "Host environments for remote clients (docs/protocol.md; "
          "tools/rdsim_client.py, or \"remote\" in a config's env) until Ctrl-C",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<ServeOptions>();
            cmd.add_option("--bind", o->bind, "Address to listen on (port * = any free port; printed on start)")->capture_default_str();
            cmd.add_option("--keys", o->keys_dir,
                           "Folder with server.key_secret and clients/*.key (rdsim keygen): CurveZMQ authentication and encryption");
            cmd.add_flag("--insecure", o->insecure, "Plain text without --keys (allowed on loopback addresses only)");
            cmd.add_option("--max-sessions", o->max_sessions, "Most envs served at once")->check(CLI::Range(1, 4096))->capture_default_str();
            cmd.add_option("--idle-timeout", o->idle_timeout, "Seconds without requests after which a session is closed")
                ->check(CLI::PositiveNumber)
                ->capture_default_str();
            return [o] { return serve_command(*o); };
          }};
}

}  // namespace rdsim
