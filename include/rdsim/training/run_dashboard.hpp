#pragma once
#include <memory>
#include <string>

namespace rdsim {

class DashboardServer;  // rdsim/dashboard/dashboard_server.hpp

// For a run trained with a dashboard (`rdsim train --dashboard ADDR`): serves the run folder
// being trained from background threads while the returned server lives; prints its address
// unless quiet. Empty `bind`: no server.
std::unique_ptr<DashboardServer> start_run_dashboard(const std::string& bind, const std::string& run_dir, bool quiet);

}  // namespace rdsim
