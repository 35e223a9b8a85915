#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rdsim/remote/curve_keys.hpp"

// `rdsim serve`'s engine: hosts environments for remote clients over ZeroMQ (docs/protocol.md).
//
// One ROUTER socket takes every client; each connection may hold one Session (its own env, made
// from its hello). One thread serves every request in arrival order, so sessions never share
// state and an env is only ever touched by that thread (renderers included); it waits in one
// blocking receive, and CurveZMQ key checks (ZAP) are answered on a second thread.
//
// Security: with `keys` set the socket is a CurveZMQ server (every byte encrypted and
// authenticated) and a ZAP handler admits only the public keys in `authorised`; refused
// attempts are logged with the peer's address. Without keys the link is plain text, which the
// constructor allows only when `insecure` is set AND the address is loopback.
//
// Hostile input: a frame above max_request_frame_bytes drops the sender's connection (ZeroMQ's
// ZMQ_MAXMSGSIZE); every other bad message gets an error reply and changes nothing; a
// connection that closes frees its session at once, an idle one after `idle_timeout`; at most
// `max_sessions` envs exist; replies to a client that does not read them are dropped once its
// queue is full (no unbounded memory).
namespace rdsim::remote {

// The sane range of the numeric options (the constructor refuses others): an idle timeout of
// 1 s to a week (a tiny one would close every session before its first request), 1 to 4096 sessions.
inline constexpr double min_idle_timeout_s = 1.0;
inline constexpr double max_idle_timeout_s = 7 * 24 * 3600.0;
inline constexpr int max_server_sessions = 4096;

struct ServerOptions {
  std::string bind = "tcp://127.0.0.1:7777";  // port * = any free port (see Server::endpoint)
  std::optional<CurveKeyPair> keys;           // the server's pair; none = plain text
  std::vector<std::string> authorised;        // client public keys (Z85) allowed in
  // What the log calls an authorised key (rdsim serve: its file's name in DIR/clients/, e.g.
  // "alice.key"), by Z85 public key; a key without one is logged as its Z85 text.
  std::map<std::string, std::string> key_names;
  bool insecure = false;                      // allow plain text (loopback addresses only)
  int max_sessions = 16;
  double idle_timeout = 300.0;                // s without a request before a session is closed
  // Where events go (sessions opened/closed, refused clients); default: stderr lines.
  std::function<void(const std::string&)> log;
};

struct ServerStats {
  long long requests = 0;  // messages received
  long long errors = 0;    // error replies sent
  // The error replies by message (at most max_error_kinds distinct ones; later new ones count under
  // "other errors"), so the summary can say what the errors were.
  std::map<std::string, long long> error_kinds;
  static constexpr std::size_t max_error_kinds = 20;
  long long refused = 0;   // connections the ZAP handler refused
  int sessions = 0;        // open now
  long long sessions_opened = 0;
};

class Server {
public:
  // Checks the options and binds. rdsim::Error for plain text on a non-loopback address, a bad
  // address, an address in use, or keys without CurveZMQ support.
  explicit Server(ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // The bound address, with the port the system chose for "*".
  const std::string& endpoint() const;

  // Serves until stop(). Call from one thread.
  void run();
  // Makes run() return within about 100 ms. Safe from any thread or a signal handler.
  void stop() { stop_.store(true); }

  // A snapshot (thread-safe).
  ServerStats stats() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::atomic<bool> stop_{false};
};

}  // namespace rdsim::remote
