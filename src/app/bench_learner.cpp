// `rdsim bench-learner`: the command line of the learner-update benchmark (rdsim/bench/bench_learner.hpp).
#include <CLI/CLI.hpp>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/bench/bench_learner.hpp"

namespace rdsim {

Command bench_learner_command_entry() {
  return {"bench-learner", "Measure the learner: time per update (zero_grad + forward + backward + Adam step) of "
          "PPO's MLPs and CNNs and SAC's critic pair; tools/bench/learner.py compares it with PyTorch",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<BenchLearnerOptions>();
            cmd.add_option("--row", o->rows, "Row to measure, by name or prefix (repeatable; default: all; --list)");
            cmd.add_flag("--list", o->list, "Print the row names and exit");
            cmd.add_option("--runs", o->runs, "Runs per row; the median is reported")->check(CLI::Range(1, 1000))->capture_default_str();
            cmd.add_option("--min-seconds", o->min_seconds, "Length of a run: updates until this many seconds (at least 3)")
                ->check(CLI::Range(0.0, 600.0))->capture_default_str();
            cmd.add_option("--gemm", o->gemm, "Matrix products: eigen or onednn (default: onednn where built in)")
                ->check(CLI::IsMember({"eigen", "onednn"}));
            cmd.add_option("--threads", o->threads, "Threads of the onednn matrix products")
                ->check(CLI::Range(1, 4096))->capture_default_str();
            add_json_option(cmd, o->json_path);
            return [o, &cmd] {
              resolve_json_option(cmd, o->json_path);
              return bench_learner_command(*o);
            };
          }};
}

}  // namespace rdsim
