// `rdsim bench-physics`: the command line of the physics fidelity gate (rdsim/bench/bench_physics.hpp).
#include <CLI/CLI.hpp>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/bench/bench_physics.hpp"

namespace rdsim {

Command bench_physics_command_entry() {
  return {"bench-physics",
          "The physics speed-ups against the solver's original work on the paper presets: the same action "
          "sequences run both ways (and once with one more solver iteration, the sequence's own sensitivity) in "
          "one process; end-effector and joint deviation and the speed ratio (exit status 1 when a mean "
          "deviation exceeds its tolerance, 5 mm Jaka, 1 cm InMoov, on a sequence the original reproduces)",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<BenchPhysicsOptions>();
            cmd.add_option("--env", o->envs, "Env to check (repeatable; default: jaka_button and inmoov_tomato)")
                ->check(CLI::IsMember({"jaka_button", "jaka_obstacle", "inmoov_tomato"}));
            cmd.add_option("--seeds", o->seeds, "Action sequences per script (random moves, held sweeps)")
                ->check(CLI::Range(1, 1000))
                ->capture_default_str();
            cmd.add_option("--steps", o->steps, "Env steps per sequence")->check(CLI::Range(1, 1000000))->capture_default_str();
            return [o] { return bench_physics_command(*o); };
          }};
}

}  // namespace rdsim
