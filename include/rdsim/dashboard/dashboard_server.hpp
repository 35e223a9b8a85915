#pragma once
#include <memory>
#include <string>
#include <vector>

// The live training dashboard: a web page (src/dashboard/web/, embedded in the binary) that lists
// the runs under some folders and plots their progress.csv as it grows. It reads only the files a
// run writes, never the trainer's memory, and serves from background threads, so a training run can
// host it (`rdsim train --dashboard`) as well as `rdsim dashboard`.
//
// HTTP interface (GET only; anything else is refused):
//   /                                the page;  /assets/<file>: its scripts and styles (embedded)
//   /api/runs                        {"poll_ms": N, "runs": [{"id", "label", "env", "algorithm", "seed"}]}
//   /api/progress?run=ID&from=BYTE   the run's progress.csv rows from byte BYTE on (0: from the top):
//                                    {"columns": [...], "rows": [[numbers or null]], "next": BYTE,
//                                     "skipped": n, "restarted": bool, "more": bool}; ask again from
//                                    "next" for the rows written since (see core/csv_reader.hpp)
// Requests larger than 64 KiB, bodies over 4 KiB and a Host header naming another site (when bound to
// loopback: a DNS-rebinding page) are refused. Slow, idle and many clients cannot hold it up: one
// event loop owns the sockets with deadlines per connection and a bound on open connections, and
// the workers that answer never wait on a client (src/dashboard/bounded_server.hpp).
namespace rdsim {

struct BindAddress {
  std::string host = "127.0.0.1";
  int port = 8097;  // visdom's port, which RobotDrlSim users know; 0 = any free port
};
// "HOST:PORT", ":PORT" or "PORT" (host 127.0.0.1); "[::1]:PORT" for IPv6. Throws rdsim::Error.
BindAddress parse_bind_address(const std::string& text);

struct DashboardOptions {
  std::vector<std::string> roots;  // folders holding run folders (or run folders themselves)
  BindAddress bind;
  int poll_ms = 500;               // how often the page asks for new rows
  int max_connections = 1024;      // open at once; a new one beyond closes the longest idle one
};

class DashboardServer {
public:
  // Binds and starts serving in the background. Throws rdsim::Error when a root is not a folder or
  // the address cannot be bound (in use, not an address of this machine).
  explicit DashboardServer(DashboardOptions options);
  ~DashboardServer();  // stops serving
  DashboardServer(const DashboardServer&) = delete;
  DashboardServer& operator=(const DashboardServer&) = delete;

  int port() const;         // the bound port (useful with port 0)
  std::string url() const;  // "http://127.0.0.1:8097/"
  // Stops serving within a fraction of a second, whatever the clients do (idempotent).
  void stop();
  // Connections open now, and the bound on them (load tests).
  int open_connections() const;
  int max_connections() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rdsim
