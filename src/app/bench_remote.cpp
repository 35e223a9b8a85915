// `rdsim bench-remote`: the command line of the remote link benchmark (rdsim/bench/bench_remote.hpp).
#include <CLI/CLI.hpp>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/bench/bench_remote.hpp"

namespace rdsim {

Command bench_remote_command_entry() {
  return {"bench-remote", "Measure remote env steps/s and round-trip latency over loopback "
          "(CurveZMQ on) next to in-process steps/s, in one run",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<BenchRemoteOptions>();
            cmd.add_option("--env", o->env, "Env to measure")->capture_default_str();
            cmd.add_option("--steps", o->steps, "Env steps per measurement")->check(CLI::PositiveNumber)->capture_default_str();
            cmd.add_option("--clients", o->clients, "Clients of the concurrent row")->check(CLI::Range(1, 64))->capture_default_str();
            cmd.add_option("--envs", o->envs, "Envs of the one-client VecEnv rows (1: none)")->check(CLI::Range(1, 64))->capture_default_str();
            cmd.add_option("--image-size", o->image_size, "Side of the raw-pixel row's images")->check(CLI::Range(8, 1024))->capture_default_str();
            cmd.add_option("--runs", o->runs, "Runs per row; the median is reported")->check(CLI::PositiveNumber)->capture_default_str();
            cmd.add_flag("--insecure", o->insecure, "Plain text instead of CurveZMQ (to see what encryption costs)");
            cmd.add_option("--json", o->json_path, "Also write the results as JSON to FILE ('-': to stdout)")->type_name("FILE");
            return [o] { return bench_remote_command(*o); };
          }};
}

}  // namespace rdsim
