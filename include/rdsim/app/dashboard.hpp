#pragma once
#include <memory>
#include <string>
#include <vector>

namespace rdsim {

// `rdsim dashboard [RUNS_DIR...]`: serves the live dashboard (rdsim/dashboard/dashboard_server.hpp)
// for the runs under the folders until interrupted (Ctrl-C) or, with serve_s > 0, for that long.
struct DashboardCommandOptions {
  std::vector<std::string> roots;     // default: runs/
  std::string bind = "127.0.0.1:8097";
  int poll_ms = 500;
  double serve_s = 0;                 // 0: until SIGINT/SIGTERM
};
int dashboard_command(const DashboardCommandOptions& options);

}  // namespace rdsim
