#pragma once
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>

// httplib's request parsing and routing behind a server whose every resource is bounded, so that
// no client, slow or idle or many, can hold up the others (see bounded_server.cpp):
//   - one event loop thread owns every socket (non-blocking, epoll); it reads a request whole
//     before any work is done on it and writes the answer out, so no worker ever waits on a
//     client;
//   - a request (request line, headers and body) is at most max_request_bytes and must arrive
//     within request_deadline of its first byte; a connection waits at most idle_deadline for its
//     next request and write_deadline for an answer to be taken;
//   - at most max_connections are open: a new one then closes the longest idle one (or, when none
//     is idle, the oldest still sending its request), so a flood of idle or slow connections
//     cannot lock a well-behaved client out;
//   - complete requests are answered by a few worker threads (httplib's handlers), which only read
//     local files;
//   - stop() returns within a fraction of a second whatever the clients do.
// Answers are never compressed (see bounded_server.cpp).
namespace rdsim {

struct ServerLimits {
  std::size_t max_request_bytes = 64 * 1024;  // request line + headers + body
  std::size_t max_body_bytes = 4 * 1024;
  int max_connections = 1024;                 // lowered to what RLIMIT_NOFILE allows
  int workers = 4;
  std::chrono::milliseconds request_deadline{10000};  // from a request's first byte to its last
  std::chrono::milliseconds idle_deadline{5000};      // waiting for the next request (keep-alive)
  std::chrono::milliseconds write_deadline{10000};    // for a client to take an answer
};

class BoundedServer : public httplib::Server {
public:
  explicit BoundedServer(ServerLimits limits);
  ~BoundedServer() override;

  // Binds and listens on host:port (0: any free port); the bound port, or -1 when it cannot.
  int bind_and_listen(const std::string& host, int port);
  // Serves on background threads until stop().
  void start();
  void stop();

  // Connections open now (tests and benchmarks).
  int open_connections() const { return open_.load(); }
  // The bound on open connections in force (limits.max_connections, or less for RLIMIT_NOFILE).
  int max_connections() const;

private:
  struct Loop;
  friend struct Loop;
  // httplib's protected request processing, for the loop's workers.
  bool process(httplib::Stream& stream, bool& close);

  ServerLimits limits_;
  std::unique_ptr<Loop> loop_;
  std::atomic<int> open_{0};
};

}  // namespace rdsim
