#include "rdsim/training/run_dashboard.hpp"

#include <cstdio>

#include "rdsim/dashboard/dashboard_server.hpp"

namespace rdsim {

std::unique_ptr<DashboardServer> start_run_dashboard(const std::string& bind, const std::string& run_dir, bool quiet) {
  if (bind.empty()) return nullptr;
  DashboardOptions options;
  options.roots = {run_dir};
  options.bind = parse_bind_address(bind);
  auto server = std::make_unique<DashboardServer>(options);
  if (!quiet) std::fprintf(stderr, "rdsim train: dashboard at %s\n", server->url().c_str());
  return server;
}

}  // namespace rdsim
