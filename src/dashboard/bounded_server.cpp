#include "bounded_server.hpp"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace rdsim {
namespace {

bool wait_for(int sock, short events, int timeout_ms) {
  pollfd p{sock, events, 0};
  for (;;) {
    const int n = ::poll(&p, 1, timeout_ms);
    if (n < 0 && errno == EINTR) continue;
    return n > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
  }
}

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

// A buffered socket stream that hands httplib at most `budget` bytes per request.
class CappedStream final : public httplib::Stream {
public:
  CappedStream(int sock, int read_timeout_ms, int write_timeout_ms)
      : sock_(sock), read_timeout_ms_(read_timeout_ms), write_timeout_ms_(write_timeout_ms) {}

  void new_request(std::size_t budget) { budget_ = budget; }
  bool exhausted() const { return budget_ == 0; }
  bool has_buffered() const { return begin_ < end_; }

  bool is_readable() const override { return has_buffered() || wait_for(sock_, POLLIN, read_timeout_ms_); }
  bool is_writable() const override { return wait_for(sock_, POLLOUT, write_timeout_ms_); }

  ssize_t read(char* ptr, size_t size) override {
    if (budget_ == 0) return -1;
    if (!has_buffered()) {
      if (!wait_for(sock_, POLLIN, read_timeout_ms_)) return -1;
      ssize_t n;
      do n = ::recv(sock_, buffer_, sizeof buffer_, 0);
      while (n < 0 && errno == EINTR);
      if (n <= 0) return n;
      begin_ = 0;
      end_ = static_cast<std::size_t>(n);
    }
    const std::size_t n = std::min({size, end_ - begin_, budget_});
    std::memcpy(ptr, buffer_ + begin_, n);
    begin_ += n;
    budget_ -= n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (!is_writable()) return -1;
    ssize_t n;
    do n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
    while (n < 0 && errno == EINTR);
    return n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override { address_of(sock_, true, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { address_of(sock_, false, ip, port); }
  socket_t socket() const override { return sock_; }

private:
  int sock_;
  int read_timeout_ms_, write_timeout_ms_;
  char buffer_[4096];
  std::size_t begin_ = 0, end_ = 0;
  std::size_t budget_ = 0;
};

}  // namespace

bool BoundedServer::process_and_close_socket(socket_t sock) {
  const int read_ms = static_cast<int>(read_timeout_sec_ * 1000 + read_timeout_usec_ / 1000);
  const int write_ms = static_cast<int>(write_timeout_sec_ * 1000 + write_timeout_usec_ / 1000);
  CappedStream stream(sock, read_ms, write_ms);
  // stop() closes the listening socket first and only then waits for the connections' tasks: a
  // closed listening socket, not is_running(), tells a keep-alive connection to end.
  auto stopping = [this] { return svr_sock_ == INVALID_SOCKET; };
  for (std::size_t left = keep_alive_max_count_; left > 0 && !stopping(); --left) {
    // Wait for the next request on this connection in short slices, so stop() is not delayed.
    bool ready = stream.has_buffered();
    for (time_t waited_ms = 0; !ready && !stopping() && waited_ms < keep_alive_timeout_sec_ * 1000; waited_ms += 100) {
      ready = wait_for(sock, POLLIN, 100);
    }
    if (!ready) break;
    stream.new_request(max_request_bytes_);
    bool closed = false;
    const bool ok = process_request(stream, left == 1 || stopping(), closed, [&](httplib::Request& req) {
      stream.get_remote_ip_and_port(req.remote_addr, req.remote_port);
      stream.get_local_ip_and_port(req.local_addr, req.local_port);
      // Answers go out uncompressed: Debian's httplib would otherwise Brotli-compress every answer a
      // browser asks for, which cost more CPU than everything else the dashboard does (measured
      // with perf: 47 % of the server's time), to save bytes on a local connection.
      req.headers.erase("Accept-Encoding");
    });
    if (!ok || closed || stream.exhausted()) break;
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return true;
}

}  // namespace rdsim
