// `rdsim envs`: what can be named in a config's "env.name".
#include "rdsim/app/envs.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim {

int envs_command() {
  std::printf("%-16s %-7s %s\n", "name", "pixels", "description");
  for (const auto& e : env_registry()) {
    // pixels: camera images as observations; "frames": drawn for people only (render_mode).
    const char* pixels = e.observes_pixels() ? "yes" : e.supports_pixels ? "frames" : "no";
    std::printf("%-16s %-7s %s\n", e.name.c_str(), pixels, e.description.c_str());
  }
  return 0;
}

Command envs_command_entry() {
  return {"envs", "List the available environments",
          [](CLI::App& cmd) -> std::function<int()> {
            (void)cmd;
            return [] { return envs_command(); };
          }};
}

}  // namespace rdsim
