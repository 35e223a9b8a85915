#pragma once
#include <httplib.h>

#include <cstddef>

// httplib's server with one more limit: what a client may send for one request (request line,
// headers and body together) is capped at max_request_bytes, and the connection is closed when a
// request reaches it. httplib 0.11 limits the request line (414) and each header line (8 KiB) and,
// with set_payload_max_length, the body (413), but not how many header lines come: without this
// cap a client could make one request use memory without end. Answers are never compressed (see
// bounded_server.cpp).
namespace rdsim {

class BoundedServer : public httplib::Server {
public:
  explicit BoundedServer(std::size_t max_request_bytes) : max_request_bytes_(max_request_bytes) {}

private:
  // Replaces httplib's per-connection loop (keep-alive, at most keep_alive_max_count_ requests)
  // with one reading through a byte-capped stream.
  bool process_and_close_socket(socket_t sock) override;

  std::size_t max_request_bytes_;
};

}  // namespace rdsim
