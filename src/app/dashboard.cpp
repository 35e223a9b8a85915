// `rdsim dashboard`.
#include "rdsim/app/dashboard.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/dashboard/dashboard_server.hpp"

namespace rdsim {

int dashboard_command(const DashboardCommandOptions& o) {
  DashboardOptions options;
  options.roots = o.roots.empty() ? std::vector<std::string>{"runs"} : o.roots;
  options.bind = parse_bind_address(o.bind);
  options.poll_ms = o.poll_ms;

  // The server's threads inherit this mask, so Ctrl-C and SIGTERM reach only the sigwait below.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  DashboardServer server(options);
  std::printf("rdsim dashboard: serving %zu folder%s at %s (Ctrl-C stops)\n", options.roots.size(),
              options.roots.size() == 1 ? "" : "s", server.url().c_str());
  std::fflush(stdout);
  if (o.serve_s > 0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.serve_s);
    for (auto now = std::chrono::steady_clock::now(); now < end; now = std::chrono::steady_clock::now()) {
      const double left = std::chrono::duration<double>(end - now).count();
      timespec wait{static_cast<time_t>(left), static_cast<long>((left - static_cast<time_t>(left)) * 1e9)};
      if (sigtimedwait(&stop_signals, nullptr, &wait) > 0) break;  // a stop signal; else time out or EINTR
    }
  } else {
    int signal = 0;
    sigwait(&stop_signals, &signal);
  }
  server.stop();
  return 0;
}

Command dashboard_command_entry() {
  return {"dashboard", "Serve a live web page plotting the runs under the folders (progress.csv), updated as they train",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<DashboardCommandOptions>();
            cmd.add_option("runs", o->roots, "Folders holding run folders, or run folders (default: runs)");
            cmd.add_option("--bind", o->bind, "HOST:PORT to listen on (loopback unless you name another address)")
                ->capture_default_str();
            cmd.add_option("--poll-ms", o->poll_ms, "How often the page asks for new rows (ms)")
                ->check(CLI::Range(50, 60000))
                ->capture_default_str();
            cmd.add_option("--for", o->serve_s, "Stop after this many seconds (default: until Ctrl-C)")->check(CLI::NonNegativeNumber);
            return [o] { return dashboard_command(*o); };
          }};
}

}  // namespace rdsim
