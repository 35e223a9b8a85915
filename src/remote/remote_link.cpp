#include "remote_link.hpp"

#include <atomic>
#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>

#include "rdsim/core/error.hpp"
#include "rdsim/remote/curve_keys.hpp"
#include "rdsim/remote/protocol.hpp"
#include "send_message.hpp"
#include "spin_wait.hpp"

namespace rdsim::remote {
namespace {

// One context (one I/O thread) for every client link of the process. Never destroyed: a
// context's destructor waits for every socket, and links may live in static objects.
zmq::context_t& client_context() {
  static auto* context = new zmq::context_t(1);
  return *context;
}

// ms a call waits for its reply before it looks at the monitor (a refused key, a lost server)
// and at its deadline; replies themselves wake it at once.
constexpr int kWaitSliceMs = 50;
// s a new link waits for its TCP connection (ZeroMQ retries a refused one every 100 ms): an absent
// server is reported after this, not after the reply timeout; a server started a moment later
// (`rdsim serve &` then a client) still gets in.
constexpr double kConnectSeconds = 3.0;

std::string next_monitor_endpoint() {
  static std::atomic<long long> counter{0};
  return "inproc://rdsim-remote-link-" + std::to_string(counter++);
}

}  // namespace

RemoteLink::RemoteLink(const RemoteEnvConfig& config)
    : endpoint_(config.remote),
      timeout_(config.remote_timeout),
      connect_deadline_(std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(std::min(config.remote_timeout, kConnectSeconds)))),
      socket_(client_context(), zmq::socket_type::dealer),
      monitor_(client_context(), zmq::socket_type::pair) {
  if (!config.server_key.empty()) {
    const std::string server = read_public_key(config.server_key);
    const CurveKeyPair client = read_secret_key(config.client_key);
    socket_.set(zmq::sockopt::curve_serverkey, server);
    socket_.set(zmq::sockopt::curve_publickey, client.public_key);
    socket_.set(zmq::sockopt::curve_secretkey, client.secret_key);
    curve_ = true;
  }
  // A hostile server cannot make this client hold a frame larger than this.
  socket_.set(zmq::sockopt::maxmsgsize, static_cast<std::int64_t>(max_reply_frame_bytes));
  socket_.set(zmq::sockopt::linger, 200);  // ms to deliver a last close
  socket_.set(zmq::sockopt::rcvtimeo, kWaitSliceMs);
  const std::string monitor = next_monitor_endpoint();
  if (zmq_socket_monitor(socket_.handle(), monitor.c_str(),
                         ZMQ_EVENT_HANDSHAKE_FAILED_AUTH | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL | ZMQ_EVENT_DISCONNECTED |
                             ZMQ_EVENT_CONNECTED | ZMQ_EVENT_CONNECT_RETRIED) != 0)
    throw Error(std::string("remote env: cannot monitor the socket: ") + zmq_strerror(zmq_errno()));
  monitor_.connect(monitor);
  try {
    socket_.connect(endpoint_);
  } catch (const zmq::error_t& e) {
    throw Error(endpoint_ + ": cannot connect: " + e.what());
  }
}

RemoteLink::~RemoteLink() {
  zmq_socket_monitor(socket_.handle(), nullptr, 0);
}

void RemoteLink::send(Message& request) {
  request.header["id"] = next_id_++;
  (void)send_message(socket_, request, zmq::send_flags::none);
}

void RemoteLink::post(Message request) {
  request.header["id"] = next_id_++;
  (void)send_message(socket_, request, zmq::send_flags::dontwait);
}

void RemoteLink::check_monitor() {
  zmq::message_t event, address;
  while (monitor_.recv(event, zmq::recv_flags::dontwait)) {
    if (event.more()) (void)monitor_.recv(address);
    std::uint16_t kind = 0;
    if (event.size() >= 2) std::memcpy(&kind, event.data(), 2);
    if (kind == ZMQ_EVENT_CONNECTED) connected_ = true;
    if (kind == ZMQ_EVENT_CONNECT_RETRIED) refused_ = true;
    if (kind == ZMQ_EVENT_HANDSHAKE_FAILED_AUTH)
      throw Error(endpoint_ + ": the server refused this client's key (its public key is not in the server's authorised "
                              "folder)");
    if (kind == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL)
      throw Error(endpoint_ + ": the CurveZMQ handshake failed (" +
                  (curve_ ? "is server_key the server's public key?" : "the server wants keys: set server_key and client_key") +
                  ")");
    if (kind == ZMQ_EVENT_DISCONNECTED) {
      // Before any reply the handshake failed; after one, the session and its env are gone.
      if (!replied_)
        throw Error(endpoint_ + ": the server closed the connection before answering (" +
                    (curve_ ? "is server_key the server's public key?" : "does the server want keys? set server_key and client_key") +
                    ")");
      throw Error(endpoint_ + ": the connection to the server was lost: the session and its env are gone");
    }
  }
}

Message RemoteLink::call(Message request) { return wait_reply(send_request(std::move(request))); }

long long RemoteLink::send_request(Message request) {
  send(request);
  return next_id_ - 1;
}

Message RemoteLink::wait_reply(long long id) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_));
  while (true) {
    // A blocking receive (one wait in the kernel) rather than zmq_poll over the socket and its
    // monitor, which costs several system calls per reply; the monitor is read when a wait slice
    // (kWaitSliceMs) passes without a reply, so a refused key or a lost server still shows at once.
    zmq::message_t first;
    std::optional<std::size_t> received;
    try {
      remote::spin_until_readable(socket_);
      received = socket_.recv(first);
    } catch (const zmq::error_t& e) {
      if (e.num() != EINTR) throw Error(endpoint_ + ": " + e.what());  // EINTR: a signal, wait on
    }
    if (!received) {
      check_monitor();
      if (!connected_ && !replied_ && Clock::now() >= connect_deadline_)
        throw Error(endpoint_ + ": " + (refused_ ? "connection refused" : "no connection") + " after " +
                    std::to_string(static_cast<long long>(std::ceil(std::min(timeout_, kConnectSeconds)))) +
                    " s: is `rdsim serve` running there?");
      if (Clock::now() >= deadline)
        throw Error(endpoint_ + ": no reply within " + std::to_string(static_cast<long long>(timeout_)) +
                    " s (is `rdsim serve` running there" + (curve_ ? ", and is server_key its public key?" : "?") + ")");
      continue;
    }
    std::vector<zmq::message_t> parts;
    parts.push_back(std::move(first));
    while (parts.back().more() && parts.size() <= static_cast<std::size_t>(max_frames)) {
      zmq::message_t part;
      (void)socket_.recv(part);  // the rest of a multipart message has arrived with its first part
      parts.push_back(std::move(part));
    }
    while (parts.back().more()) {  // more frames than any reply has: drain and refuse
      zmq::message_t rest;
      (void)socket_.recv(rest);
      if (!rest.more()) throw Error(endpoint_ + ": bad reply from the server: too many frames");
    }
    std::vector<std::string_view> frames;
    for (const auto& p : parts) frames.emplace_back(static_cast<const char*>(p.data()), p.size());
    Message reply;
    try {
      reply = decode_message(frames, max_reply_frame_bytes, max_reply_frame_bytes);
    } catch (const Error& e) {
      throw Error(endpoint_ + ": bad reply from the server: " + e.what());
    }
    const auto got = reply.header.find("id");
    if (got == reply.header.end() || !got->is_number_integer() || got->get<long long>() != id) {
      if (got != reply.header.end() && got->is_null() && reply.header.contains("error"))
        throw Error(endpoint_ + ": " + reply.header["error"].dump());
      continue;  // the late reply of an earlier request that timed out
    }
    const auto error = reply.header.find("error");
    replied_ = true;
    if (error != reply.header.end()) throw Error(endpoint_ + ": " + (error->is_string() ? error->get<std::string>() : error->dump()));
    return reply;
  }
}

}  // namespace rdsim::remote
