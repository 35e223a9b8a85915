#include "rdsim/remote/server.hpp"

#include <zmq.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "rdsim/core/error.hpp"
#include "rdsim/remote/endpoint.hpp"
#include "rdsim/remote/protocol.hpp"
#include "rdsim/remote/request.hpp"
#include "rdsim/remote/session.hpp"
#include "send_message.hpp"
#include "spin_wait.hpp"

namespace rdsim::remote {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kPollMs = 100;        // how soon stop() is noticed (the receive timeout of the loops)
constexpr int kMonitorMs = 10;      // disconnections are read at least this often while requests flow
// What one client can make the server hold, in messages (ZeroMQ counts messages, not bytes):
// replies queued for a client that does not read them (further ones are dropped), and requests
// received but not yet served (further ones wait in the client's own TCP buffers). In bytes: at
// most 8 of its session's largest reply (8 x 6 MiB for two 1024 x 1024 cameras) plus the
// kernel's socket buffers, and 64 x 64 KiB of requests.
constexpr int kSendQueueLimit = 8;
constexpr int kReceiveQueueLimit = 64;
constexpr std::size_t kCurveOverheadBytes = 64;  // a CurveZMQ MESSAGE adds 33 bytes to its payload
const char* const kZapEndpoint = "inproc://zeromq.zap.01";  // fixed by the ZAP specification (RFC 27)
const char* const kMonitorEndpoint = "inproc://rdsim-serve-monitor";

std::string z85(const void* key32) {
  char text[41];
  zmq_z85_encode(text, static_cast<const std::uint8_t*>(key32), 32);
  return text;
}

std::string raw_key(const std::string& z85_key) {
  std::uint8_t bytes[32];
  if (z85_key.size() != 40 || !zmq_z85_decode(bytes, z85_key.c_str())) throw Error("not a CurveZMQ public key: " + z85_key);
  return std::string(reinterpret_cast<const char*>(bytes), 32);
}

std::string meta(zmq::message_t& m, const char* property) {
  const char* v = zmq_msg_gets(m.handle(), property);
  return v ? v : "";
}

}  // namespace

struct Server::Impl {
  ServerOptions options;
  zmq::context_t context{1};
  zmq::socket_t zap{context, zmq::socket_type::rep};
  zmq::socket_t router{context, zmq::socket_type::router};
  zmq::socket_t monitor{context, zmq::socket_type::pair};
  std::string endpoint;
  std::set<std::string> authorised;  // raw 32-byte public keys
  std::map<std::string, std::string> key_names;  // raw 32-byte public key -> its name in the log

  struct Entry {
    std::unique_ptr<Session> session;
    Clock::time_point last;
    int fd = -1;              // the connection's socket (ZMQ_SRCFD), to notice it closing
    long long number = 0;     // for the log
  };
  std::map<std::string, Entry> sessions;  // by ZeroMQ routing id (one per connection)
  long long next_number = 1;
  Clock::time_point last_sweep = Clock::now();

  Clock::time_point last_monitor = Clock::now();

  mutable std::mutex stats_mutex;
  ServerStats stats;
  mutable std::mutex log_mutex;  // the ZAP thread logs refusals too

  void log(const std::string& line) const {
    std::lock_guard<std::mutex> lock(log_mutex);
    if (options.log) options.log(line);
    else std::fprintf(stderr, "rdsim serve: %s\n", line.c_str());
  }
  void count(long long ServerStats::*field) {
    std::lock_guard<std::mutex> lock(stats_mutex);
    ++(stats.*field);
  }
  // An error reply: counted by its message, and logged with the session it went to (the first
  // kLoggedErrors of them: hostile input must not flood the log).
  void count_error(const std::string& id, const std::string& message) {
    static constexpr long long kLoggedErrors = 20;
    long long n = 0;
    {
      std::lock_guard<std::mutex> lock(stats_mutex);
      n = ++stats.errors;
      auto& kinds = stats.error_kinds;
      if (kinds.count(message) || kinds.size() < ServerStats::max_error_kinds) ++kinds[message];
      else ++kinds["other errors"];
    }
    if (n > kLoggedErrors) return;
    const auto it = sessions.find(id);
    const std::string who = it == sessions.end() ? "a client without a session" : "session " + std::to_string(it->second.number);
    log("error reply to " + who + ": " + message + (n == kLoggedErrors ? " (further errors are counted, not logged)" : ""));
  }
  void sync_session_count() {
    std::lock_guard<std::mutex> lock(stats_mutex);
    stats.sessions = static_cast<int>(sessions.size());
  }

  void close_session(std::map<std::string, Entry>::iterator it, const char* why) {
    log("session " + std::to_string(it->second.number) + " closed (" + why + ") after " +
        std::to_string(it->second.session->steps()) + " steps");
    sessions.erase(it);
    sync_session_count();
  }

  void serve_zap(const std::atomic<bool>& stop);
  void serve_monitor();
  void serve_router(zmq::message_t& id);
  void serve_one(zmq::message_t& id, std::vector<zmq::message_t>& parts, bool too_many);
  Message answer(const std::string& id, zmq::message_t& first, const ParsedRequest& parsed, int fd);
  void send(const zmq::message_t& id, bool envelope, const Message& reply);
  void sweep_idle();
};

Server::Server(ServerOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.options = std::move(options);
  const ServerOptions& o = s.options;
  check_tcp_endpoint(o.bind, "serve --bind");
  if (o.max_sessions < 1 || o.max_sessions > max_server_sessions)
    throw Error("serve: --max-sessions: expected 1 to " + std::to_string(max_server_sessions));
  if (!(o.idle_timeout >= min_idle_timeout_s && o.idle_timeout <= max_idle_timeout_s))
    throw Error("serve: --idle-timeout: expected " + std::to_string(static_cast<int>(min_idle_timeout_s)) + " to " +
                std::to_string(static_cast<long long>(max_idle_timeout_s)) + " seconds");
  if (!o.keys) {
    if (!o.insecure) throw Error("serve: give --keys DIR (CurveZMQ authentication and encryption) or --insecure (plain text, loopback only)");
    if (!is_loopback_endpoint(o.bind))
      throw Error("serve: plain text (--insecure) is allowed only on a loopback address such as tcp://127.0.0.1:7777, not " +
                  o.bind + ": use --keys DIR");
  } else {
    if (!zmq_has("curve")) throw Error("serve: this libzmq was built without CurveZMQ");
    for (const std::string& k : o.authorised) s.authorised.insert(raw_key(k));
    for (const auto& [k, name] : o.key_names) s.key_names[raw_key(k)] = name;
    // The ZAP handler must be bound before the socket that consults it.
    s.zap.bind(kZapEndpoint);
    s.router.set(zmq::sockopt::curve_server, 1);
    s.router.set(zmq::sockopt::curve_secretkey, o.keys->secret_key);
    s.router.set(zmq::sockopt::zap_domain, "rdsim");
  }
  // Under CurveZMQ the limit applies to the encrypted message, 33 bytes longer (command name,
  // nonce, MAC, flags): allow for them, so the documented limit holds for what a client sends;
  // decode_message refuses a frame above max_request_frame_bytes with an error reply.
  s.router.set(zmq::sockopt::maxmsgsize,
               static_cast<std::int64_t>(max_request_frame_bytes + (o.keys ? kCurveOverheadBytes : 0)));
  if (is_ipv6_endpoint(o.bind)) s.router.set(zmq::sockopt::ipv6, 1);
  s.router.set(zmq::sockopt::sndhwm, kSendQueueLimit);
  s.router.set(zmq::sockopt::rcvhwm, kReceiveQueueLimit);
  s.router.set(zmq::sockopt::linger, 0);
  s.router.set(zmq::sockopt::handshake_ivl, 5000);  // ms: a stalled handshake is dropped
  s.router.set(zmq::sockopt::rcvtimeo, kPollMs);
  s.zap.set(zmq::sockopt::rcvtimeo, kPollMs);
  if (zmq_socket_monitor(s.router.handle(), kMonitorEndpoint, ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL |
                                                                    ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL) != 0)
    throw Error(std::string("serve: cannot monitor the socket: ") + zmq_strerror(zmq_errno()));
  s.monitor.connect(kMonitorEndpoint);
  try {
    s.router.bind(bindable_endpoint(o.bind));
  } catch (const zmq::error_t& e) {
    throw Error("serve: cannot bind " + o.bind + ": " + e.what());
  }
  s.endpoint = s.router.get(zmq::sockopt::last_endpoint);
}

Server::~Server() = default;

const std::string& Server::endpoint() const { return impl_->endpoint; }

ServerStats Server::stats() const {
  std::lock_guard<std::mutex> lock(impl_->stats_mutex);
  return impl_->stats;
}

namespace {

// Receives one message part; nothing after the socket's receive timeout or a signal (EINTR).
bool receive(zmq::socket_t& socket, zmq::message_t& part) {
  try {
    return socket.recv(part).has_value();
  } catch (const zmq::error_t& e) {
    if (e.num() == EINTR) return false;  // a signal: the caller looks at stop_
    throw Error(std::string("serve: ") + e.what());
  }
}

// Runs `body` on its own thread until this object goes, which sets `done` and joins it.
struct Helper {
  std::atomic<bool> done{false};
  std::thread thread;
  template <class F> explicit Helper(F body) : thread([this, body] { body(done); }) {}
  ~Helper() {
    done.store(true);
    thread.join();
  }
};

}  // namespace

void Server::run() {
  Impl& s = *impl_;
  // ZAP requests (CurveZMQ key checks) are answered on their own thread, so this loop can wait in
  // one blocking receive on the router: zmq_poll over three sockets cost several system calls per
  // request. The ZAP thread touches only the key set (read-only), the stats and the log (locked).
  std::optional<Helper> zap;
  if (s.options.keys) zap.emplace([&s, this](const std::atomic<bool>& done) {
    while (!done.load() && !stop_.load()) s.serve_zap(done);
  });
  while (!stop_.load()) {
    zmq::message_t id;
    remote::spin_until_readable(s.router);
    const bool got = receive(s.router, id);
    // Disconnections before a hello (a new connection may reuse a closed one's fd), after a
    // quiet wait, and every kMonitorMs, so a session never outlives its connection for long.
    const auto now = Clock::now();
    if (!got || now - s.last_monitor >= std::chrono::milliseconds(kMonitorMs) || !s.sessions.count(id.to_string())) {
      s.last_monitor = now;
      s.serve_monitor();
    }
    if (got) s.serve_router(id);
    s.sweep_idle();
  }
}

void Server::Impl::serve_zap(const std::atomic<bool>& stop) {
  while (!stop.load()) {
    std::vector<zmq::message_t> f;
    zmq::message_t part;
    if (!receive(zap, part)) return;
    f.push_back(std::move(part));
    while (f.back().more() && f.size() < 16) {
      zmq::message_t next;
      (void)zap.recv(next);
      f.push_back(std::move(next));
    }
    // version, request id, domain, address, identity, mechanism, credentials...
    const std::string version = f.size() > 0 ? f[0].to_string() : "", request_id = f.size() > 1 ? f[1].to_string() : "";
    const std::string address = f.size() > 3 ? f[3].to_string() : "?";
    const std::string mechanism = f.size() > 5 ? f[5].to_string() : "";
    bool ok = false;
    std::string user;
    if (mechanism == "CURVE" && f.size() > 6 && f[6].size() == 32) {
      const std::string key(static_cast<const char*>(f[6].data()), 32);
      ok = authorised.count(key) > 0;
      const auto name = key_names.find(key);
      user = ok && name != key_names.end() ? name->second : z85(key.data());
      if (!ok) {
        count(&ServerStats::refused);
        log("refused client key " + user + " from " + address + ": not an authorised key");
      }
    } else {
      count(&ServerStats::refused);
      log("refused a " + mechanism + " connection from " + address + ": CurveZMQ required");
    }
    zap.send(zmq::str_buffer("1.0"), zmq::send_flags::sndmore);
    zap.send(zmq::buffer(request_id), zmq::send_flags::sndmore);
    zap.send(zmq::buffer(std::string(ok ? "200" : "400")), zmq::send_flags::sndmore);
    zap.send(zmq::buffer(std::string(ok ? "OK" : "not authorised")), zmq::send_flags::sndmore);
    zap.send(zmq::buffer(user), zmq::send_flags::sndmore);
    zap.send(zmq::str_buffer(""), zmq::send_flags::none);
  }
}

void Server::Impl::serve_monitor() {
  while (true) {
    zmq::message_t event, address;
    if (!monitor.recv(event, zmq::recv_flags::dontwait)) return;
    if (event.more()) (void)monitor.recv(address);
    if (event.size() < 6) continue;
    std::uint16_t kind = 0;
    std::uint32_t value = 0;
    std::memcpy(&kind, event.data(), 2);
    std::memcpy(&value, static_cast<const char*>(event.data()) + 2, 4);
    if (kind == ZMQ_EVENT_DISCONNECTED) {
      for (auto it = sessions.begin(); it != sessions.end();) {
        auto next = std::next(it);
        if (it->second.fd == static_cast<int>(value)) close_session(it, "the client disconnected");
        it = next;
      }
    } else {
      // A refused attempt like any other (counted and logged), but ZeroMQ names no peer address
      // for a failed handshake.
      count(&ServerStats::refused);
      log(std::string("refused a connection that failed the CurveZMQ handshake: ") +
          (kind == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL && value == ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH
               ? "a plain-text client (every client needs keys)"
               : "a plain-text client, or a wrong server key"));
    }
  }
}

void Server::Impl::serve_router(zmq::message_t& id) {
  std::vector<zmq::message_t> parts;
  bool too_many = false;
  for (bool more = id.more(); more;) {
    zmq::message_t part;
    (void)router.recv(part);  // the rest of a multipart message has arrived with its first part
    more = part.more();
    if (parts.size() <= static_cast<std::size_t>(max_frames)) parts.push_back(std::move(part));
    else too_many = true;  // read and dropped: a peer cannot make us hold more
  }
  serve_one(id, parts, too_many);
}

void Server::Impl::serve_one(zmq::message_t& id, std::vector<zmq::message_t>& parts, bool too_many) {
  count(&ServerStats::requests);
  if (parts.empty()) return;
  // A REQ client puts an empty delimiter frame first; the reply must carry it back.
  const bool envelope = parts.size() > 1 && parts[0].size() == 0;
  std::vector<std::string_view> frames;
  for (std::size_t i = envelope ? 1 : 0; i < parts.size(); ++i)
    frames.emplace_back(static_cast<const char*>(parts[i].data()), parts[i].size());
  ParsedRequest parsed;
  if (too_many) {
    parsed.id = nullptr;
    parsed.error = "message has more than " + std::to_string(max_frames) + " frames";
  } else {
    parsed = parse_request(frames);
  }
  const std::string key(static_cast<const char*>(id.data()), id.size());
  Message reply;
  try {
    reply = answer(key, parts[0], parsed, parts[0].get(ZMQ_SRCFD));
  } catch (const Error& e) {
    reply = error_reply(parsed.id, e.what());
  } catch (const std::exception& e) {
    reply = error_reply(parsed.id, std::string("internal error: ") + e.what());
  }
  if (reply.header.contains("error")) count_error(key, reply.header["error"].get<std::string>());
  send(id, envelope, reply);
}

Message Server::Impl::answer(const std::string& id, zmq::message_t& first, const ParsedRequest& parsed, int fd) {
  if (!parsed.request) return error_reply(parsed.id, parsed.error);
  const Request& q = *parsed.request;
  auto it = sessions.find(id);
  if (q.kind == RequestKind::Hello) {
    if (it != sessions.end()) throw Error("hello: this connection already has a session: send close first");
    if (static_cast<int>(sessions.size()) >= options.max_sessions)
      throw Error("hello: the server is full (" + std::to_string(options.max_sessions) + " sessions, --max-sessions): try later");
    auto session = std::make_unique<Session>(q);
    Message reply = session->hello_reply(q.id);
    const long long number = next_number++;
    const std::string user = meta(first, "User-Id"), peer = meta(first, "Peer-Address");
    log("session " + std::to_string(number) + " opened: " + session->config().name + " for " +
        (user.empty() ? std::string("a plain-text client") : "client " + user) + " from " + (peer.empty() ? "?" : peer));
    sessions[id] = Entry{std::move(session), Clock::now(), fd, number};
    count(&ServerStats::sessions_opened);
    sync_session_count();
    return reply;
  }
  if (it == sessions.end())
    throw Error(std::string(to_string(q.kind)) +
                ": no session on this connection: send hello first (a session ends with close, after " +
                std::to_string(static_cast<long long>(options.idle_timeout)) + " s without requests, or when its connection drops)");
  it->second.last = Clock::now();
  it->second.fd = fd;
  if (q.kind == RequestKind::Close) {
    close_session(it, "the client closed it");
    return reply_to(q.id, q.kind);
  }
  return it->second.session->handle(q);
}

void Server::Impl::send(const zmq::message_t& id, bool envelope, const Message& reply) {
  try {
    // ROUTER sends never block: a peer that is gone or whose queue is full loses the reply.
    router.send(zmq::buffer(id.data(), id.size()), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
    if (envelope) router.send(zmq::const_buffer(nullptr, 0), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
    (void)send_message(router, reply, zmq::send_flags::dontwait);
  } catch (const zmq::error_t&) {
    // EHOSTUNREACH / EAGAIN: nothing more to do for this peer.
  }
}

void Server::Impl::sweep_idle() {
  const auto now = Clock::now();
  const auto limit = std::chrono::duration<double>(options.idle_timeout);
  if (now - last_sweep < std::min<std::chrono::duration<double>>(std::chrono::seconds(1), limit / 4)) return;
  last_sweep = now;
  for (auto it = sessions.begin(); it != sessions.end();) {
    auto next = std::next(it);
    if (now - it->second.last > limit) close_session(it, "idle timeout");
    it = next;
  }
}

}  // namespace rdsim::remote
