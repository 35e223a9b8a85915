#include "bounded_server.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <vector>

namespace rdsim {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kTickMs = 100;                       // deadlines are checked this often
constexpr std::size_t kMaxAnswerBytes = 64 << 20;  // what one answer may hold (the handlers stay far below)
constexpr auto kDrainTime = std::chrono::seconds(1);

struct Peer {
  std::string remote_ip, local_ip;
  int remote_port = 0, local_port = 0;
};

void address_of(int sock, bool peer, std::string& ip, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  if ((peer ? ::getpeername(sock, reinterpret_cast<sockaddr*>(&addr), &len)
            : ::getsockname(sock, reinterpret_cast<sockaddr*>(&addr), &len)) != 0) {
    return;
  }
  char text[INET6_ADDRSTRLEN] = "";
  if (addr.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&addr);
    ::inet_ntop(AF_INET, &a->sin_addr, text, sizeof text);
    port = ntohs(a->sin_port);
  } else if (addr.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&addr);
    ::inet_ntop(AF_INET6, &a->sin6_addr, text, sizeof text);
    port = ntohs(a->sin6_port);
  }
  ip = text;
}

// httplib reads one complete request from memory and writes its answer to memory: the worker
// that runs it never touches the socket.
class BufferStream final : public httplib::Stream {
public:
  BufferStream(const std::string& request, const Peer& peer) : in_(request), peer_(peer) {}

  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const std::size_t n = std::min(size, in_.size() - pos_);
    std::memcpy(ptr, in_.data() + pos_, n);
    pos_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (out_.size() + size > kMaxAnswerBytes) return -1;
    out_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = peer_.remote_ip;
    port = peer_.remote_port;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = peer_.local_ip;
    port = peer_.local_port;
  }
  socket_t socket() const override { return INVALID_SOCKET; }
  std::string take() { return std::move(out_); }

private:
  const std::string& in_;
  std::size_t pos_ = 0;
  std::string out_;
  Peer peer_;
};

// The value of header `name` (lower case, with its colon) in the header block, or "".
std::string header_value(const std::string& lower_headers, const std::string& name) {
  const std::size_t at = lower_headers.find("\r\n" + name);
  if (at == std::string::npos) return "";
  const std::size_t start = at + 2 + name.size(), end = lower_headers.find("\r\n", start);
  std::string v = lower_headers.substr(start, end - start);
  v.erase(0, v.find_first_not_of(" \t"));
  while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.pop_back();
  return v;
}

struct Framing {
  std::size_t end = 0;       // bytes of the first request in the buffer; 0 while it is incomplete
  bool close_after = false;  // its body is not read (too large, or chunked): close after answering
  bool too_large = false;    // over the request limit: refuse
};

// Where the first request in `in` ends: its headers, and the body their Content-Length announces
// when that is within max_body (httplib refuses a larger one from the headers alone, 413).
Framing frame_request(const std::string& in, const ServerLimits& limits) {
  Framing f;
  const std::size_t head_end = in.find("\r\n\r\n");
  if (head_end == std::string::npos) {
    f.too_large = in.size() >= limits.max_request_bytes;
    return f;
  }
  const std::size_t head = head_end + 4;
  if (head > limits.max_request_bytes) {
    f.too_large = true;
    return f;
  }
  std::string lower = in.substr(0, head);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  std::size_t body = 0;
  const std::string length = header_value(lower, "content-length:");
  if (!header_value(lower, "transfer-encoding:").empty()) {
    f.close_after = true;
  } else if (!length.empty()) {
    const bool digits = length.size() <= 12 && length.find_first_not_of("0123456789") == std::string::npos;
    const std::size_t n = digits ? std::stoull(length) : SIZE_MAX;
    if (n > limits.max_body_bytes || head + n > limits.max_request_bytes) f.close_after = true;
    else body = n;
  }
  if (in.size() < head + body) return f;
  f.end = head + body;
  return f;
}

std::string plain_answer(int status, const char* reason, const std::string& text) {
  return "HTTP/1.1 " + std::to_string(status) + " " + reason + "\r\nContent-Type: application/json\r\nContent-Length: " +
         std::to_string(text.size()) + "\r\nConnection: close\r\n\r\n" + text;
}

}  // namespace

struct BoundedServer::Loop {
  enum class State { Idle, Receiving, Working, Sending, Draining };
  struct Conn {
    int fd = -1;
    std::uint64_t id = 0;
    Peer peer;
    State state = State::Idle;
    std::string in, out;
    std::size_t sent = 0;
    bool close_after = false;
    Clock::time_point since, deadline;  // since: when it entered its state (which to close first)
  };
  struct Job {
    int fd;
    std::uint64_t id;
    std::string request;
    Peer peer;
  };
  struct Result {
    int fd;
    std::uint64_t id;
    std::string answer;
    bool close;
  };

  BoundedServer& server;
  const ServerLimits& limits;
  int max_connections = 0;
  int listen_fd = -1, epoll_fd = -1, wake_fd = -1;
  std::unordered_map<int, Conn> conns;
  std::uint64_t next_id = 1;
  Clock::time_point accept_paused_until{};
  bool accept_paused = false;

  std::mutex mutex;  // jobs, results, stopping
  std::condition_variable work;
  std::deque<Job> jobs;
  std::vector<Result> results;
  bool stopping = false;
  std::atomic<bool> stop_requested{false};
  std::thread io;
  std::vector<std::thread> workers;

  Loop(BoundedServer& s, const ServerLimits& l) : server(s), limits(l) {}
  ~Loop() {
    for (int fd : {listen_fd, epoll_fd, wake_fd})
      if (fd >= 0) ::close(fd);
  }

  void wake() {
    const std::uint64_t one = 1;
    (void)!::write(wake_fd, &one, sizeof one);
  }
  void watch(Conn& c, std::uint32_t events) {
    epoll_event ev{};
    ev.events = events;
    ev.data.fd = c.fd;
    ::epoll_ctl(epoll_fd, EPOLL_CTL_MOD, c.fd, &ev);
  }
  void enter(Conn& c, State state, Clock::duration deadline) {
    c.state = state;
    c.since = Clock::now();
    c.deadline = deadline == Clock::duration::max() ? Clock::time_point::max() : c.since + deadline;
  }
  void close_conn(int fd) {
    ::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, fd, nullptr);
    ::close(fd);
    conns.erase(fd);
    server.open_.store(static_cast<int>(conns.size()));
  }

  // Makes room for one more: closes the longest idle connection, else the oldest still sending
  // its request. False when every connection is being answered.
  bool evict() {
    Conn* victim = nullptr;
    for (State wanted : {State::Idle, State::Draining, State::Receiving}) {
      for (auto& [fd, c] : conns)
        if (c.state == wanted && (!victim || c.since < victim->since)) victim = &c;
      if (victim) break;
    }
    if (!victim) return false;
    close_conn(victim->fd);
    return true;
  }

  void accept_all() {
    for (int k = 0; k < 64; ++k) {
      const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if ((errno == EMFILE || errno == ENFILE) && evict()) continue;
        if (errno == EMFILE || errno == ENFILE) pause_accepting();
        return;
      }
      if (static_cast<int>(conns.size()) >= max_connections && !evict()) {
        ::close(fd);  // every connection is being answered: this one must try again
        continue;
      }
      const int yes = 1;
      ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
      Conn& c = conns[fd];
      c.fd = fd;
      c.id = next_id++;
      address_of(fd, true, c.peer.remote_ip, c.peer.remote_port);
      address_of(fd, false, c.peer.local_ip, c.peer.local_port);
      enter(c, State::Idle, limits.idle_deadline);
      epoll_event ev{};
      ev.events = EPOLLIN;
      ev.data.fd = fd;
      ::epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &ev);
      server.open_.store(static_cast<int>(conns.size()));
    }
  }
  void pause_accepting() {
    ::epoll_ctl(epoll_fd, EPOLL_CTL_DEL, listen_fd, nullptr);
    accept_paused = true;
    accept_paused_until = Clock::now() + std::chrono::milliseconds(kTickMs);
  }
  void resume_accepting() {
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.fd = listen_fd;
    ::epoll_ctl(epoll_fd, EPOLL_CTL_ADD, listen_fd, &ev);
    accept_paused = false;
  }

  // Answers that the loop writes itself (a request over the limits), then closes.
  void refuse(Conn& c, const std::string& answer) {
    c.in.clear();
    c.close_after = true;
    start_sending(c, answer);
  }

  void dispatch(Conn& c) {
    const Framing f = frame_request(c.in, limits);
    if (f.too_large) return refuse(c, plain_answer(400, "Bad Request", "{\"error\": \"request too large\"}"));
    if (f.end == 0) return;
    Job job{c.fd, c.id, c.in.substr(0, f.end), c.peer};
    c.in.erase(0, f.end);
    c.close_after = f.close_after;
    enter(c, State::Working, Clock::duration::max());
    watch(c, 0);  // pipelined bytes wait in the kernel until this answer is out
    {
      std::lock_guard<std::mutex> lock(mutex);
      jobs.push_back(std::move(job));
    }
    work.notify_one();
  }

  void start_sending(Conn& c, std::string answer) {
    c.out = std::move(answer);
    c.sent = 0;
    enter(c, State::Sending, limits.write_deadline);
    watch(c, EPOLLOUT);
    send_some(c);
  }

  // False when the connection was closed.
  bool send_some(Conn& c) {
    while (c.sent < c.out.size()) {
      const ssize_t n = ::send(c.fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
      if (n <= 0) {
        close_conn(c.fd);
        return false;
      }
      c.sent += static_cast<std::size_t>(n);
    }
    c.out = std::string();
    if (c.close_after) {
      // Stop sending, and read what the client still sends for a moment: closing with unread
      // bytes would reset the connection and could destroy the answer before it is read.
      ::shutdown(c.fd, SHUT_WR);
      c.in.clear();
      enter(c, State::Draining, kDrainTime);
      watch(c, EPOLLIN);
      return true;
    }
    enter(c, c.in.empty() ? State::Idle : State::Receiving, c.in.empty() ? limits.idle_deadline : limits.request_deadline);
    watch(c, EPOLLIN);
    dispatch(c);
    return true;
  }

  void receive(Conn& c) {
    char buf[16384];
    for (;;) {
      const ssize_t n = ::recv(c.fd, buf, sizeof buf, 0);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
      if (n <= 0) return close_conn(c.fd);
      if (c.state == State::Draining) continue;  // discarded
      if (c.state == State::Idle) enter(c, State::Receiving, limits.request_deadline);
      c.in.append(buf, static_cast<std::size_t>(n));
      if (c.in.size() >= limits.max_request_bytes) break;  // frame_request decides; the rest stays in the kernel
    }
    if (c.state == State::Receiving) dispatch(c);
  }

  void on_event(int fd, std::uint32_t events) {
    auto it = conns.find(fd);
    if (it == conns.end()) return;
    Conn& c = it->second;
    if (events & (EPOLLERR | EPOLLHUP)) return close_conn(fd);
    if ((events & EPOLLOUT) && c.state == State::Sending) {
      send_some(c);
      return;
    }
    if ((events & EPOLLIN) && (c.state == State::Idle || c.state == State::Receiving || c.state == State::Draining)) receive(c);
  }

  void take_results() {
    std::uint64_t count;
    (void)!::read(wake_fd, &count, sizeof count);
    std::vector<Result> done;
    {
      std::lock_guard<std::mutex> lock(mutex);
      done.swap(results);
    }
    for (Result& r : done) {
      auto it = conns.find(r.fd);
      if (it == conns.end() || it->second.id != r.id) continue;  // closed meanwhile
      Conn& c = it->second;
      c.close_after = c.close_after || r.close;
      if (r.answer.empty()) {
        close_conn(c.fd);
        continue;
      }
      start_sending(c, std::move(r.answer));
    }
  }

  void sweep(Clock::time_point now) {
    std::vector<int> late;
    for (auto& [fd, c] : conns)
      if (now >= c.deadline) late.push_back(fd);
    for (int fd : late) close_conn(fd);
  }

  void run() {
    std::vector<epoll_event> events(256);
    auto last_sweep = Clock::now();
    while (!stop_requested.load()) {
      const int n = ::epoll_wait(epoll_fd, events.data(), static_cast<int>(events.size()), kTickMs);
      for (int i = 0; i < n; ++i) {
        const int fd = events[static_cast<std::size_t>(i)].data.fd;
        if (fd == wake_fd) take_results();
        else if (fd == listen_fd) accept_all();
        else on_event(fd, events[static_cast<std::size_t>(i)].events);
      }
      const auto now = Clock::now();
      if (accept_paused && now >= accept_paused_until) resume_accepting();
      if (now - last_sweep >= std::chrono::milliseconds(kTickMs)) {
        sweep(now);
        last_sweep = now;
      }
    }
    std::vector<int> all;
    for (auto& [fd, c] : conns) all.push_back(fd);
    for (int fd : all) close_conn(fd);
  }

  void serve_jobs() {
    for (;;) {
      Job job;
      {
        std::unique_lock<std::mutex> lock(mutex);
        work.wait(lock, [&] { return stopping || !jobs.empty(); });
        if (stopping) return;
        job = std::move(jobs.front());
        jobs.pop_front();
      }
      BufferStream stream(job.request, job.peer);
      bool close = false;
      const bool ok = server.process(stream, close);
      Result r{job.fd, job.id, stream.take(), close || !ok};
      {
        std::lock_guard<std::mutex> lock(mutex);
        results.push_back(std::move(r));
      }
      wake();
    }
  }
};

BoundedServer::BoundedServer(ServerLimits limits) : limits_(limits) {}

BoundedServer::~BoundedServer() { stop(); }

int BoundedServer::max_connections() const { return loop_ ? loop_->max_connections : limits_.max_connections; }

bool BoundedServer::process(httplib::Stream& stream, bool& close) {
  return process_request(stream, false, close, [](httplib::Request& req) {
    // Answers go out uncompressed: Debian's httplib would otherwise Brotli-compress every answer a
    // browser asks for, which cost more CPU than everything else the dashboard does (measured
    // with perf: 47 % of the server's time), to save bytes on a local connection.
    req.headers.erase("Accept-Encoding");
  });
}

int BoundedServer::bind_and_listen(const std::string& host, int port) {
  loop_ = std::make_unique<Loop>(*this, limits_);
  Loop& l = *loop_;
  // Each connection is a descriptor: stay within RLIMIT_NOFILE (raised to its hard limit when
  // needed), leaving room for the files the handlers open.
  constexpr int kReserve = 64;
  constexpr int kMinConnections = 8;
  rlimit files{};
  if (::getrlimit(RLIMIT_NOFILE, &files) == 0) {
    const rlim_t wanted = static_cast<rlim_t>(limits_.max_connections + kReserve);
    if (files.rlim_cur < wanted && files.rlim_cur != RLIM_INFINITY) {
      files.rlim_cur = files.rlim_max == RLIM_INFINITY ? wanted : std::min(files.rlim_max, wanted);
      ::setrlimit(RLIMIT_NOFILE, &files);
      ::getrlimit(RLIMIT_NOFILE, &files);
    }
    const long allowed = files.rlim_cur == RLIM_INFINITY ? limits_.max_connections : static_cast<long>(files.rlim_cur) - kReserve;
    l.max_connections = static_cast<int>(std::clamp<long>(allowed, kMinConnections, std::max(limits_.max_connections, kMinConnections)));
  } else {
    l.max_connections = std::max(limits_.max_connections, kMinConnections);
  }

  addrinfo hints{}, *found = nullptr;
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  const std::string service = std::to_string(port);
  if (::getaddrinfo(host.empty() ? nullptr : host.c_str(), service.c_str(), &hints, &found) != 0) return -1;
  for (addrinfo* a = found; a && l.listen_fd < 0; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    // SO_REUSEADDR only (restart without waiting for TIME_WAIT); never SO_REUSEPORT, which would
    // let a second server share the port silently.
    const int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, 1024) == 0) l.listen_fd = fd;
    else ::close(fd);
  }
  ::freeaddrinfo(found);
  if (l.listen_fd < 0) return -1;
  std::string ip;
  int bound = -1;
  address_of(l.listen_fd, false, ip, bound);
  return bound;
}

void BoundedServer::start() {
  Loop& l = *loop_;
  l.epoll_fd = ::epoll_create1(EPOLL_CLOEXEC);
  l.wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  for (int fd : {l.listen_fd, l.wake_fd}) {
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.fd = fd;
    ::epoll_ctl(l.epoll_fd, EPOLL_CTL_ADD, fd, &ev);
  }
  for (int k = 0; k < limits_.workers; ++k) l.workers.emplace_back([&l] { l.serve_jobs(); });
  l.io = std::thread([&l] { l.run(); });
}

void BoundedServer::stop() {
  if (!loop_) return;
  Loop& l = *loop_;
  l.stop_requested.store(true);
  {
    std::lock_guard<std::mutex> lock(l.mutex);
    l.stopping = true;
  }
  l.work.notify_all();
  if (l.wake_fd >= 0) l.wake();
  if (l.io.joinable()) l.io.join();
  for (auto& w : l.workers) w.join();  // each finishes the answer it is making (local files only)
  l.workers.clear();
  loop_.reset();
  open_.store(0);
}

}  // namespace rdsim
