#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

// The commands of `rdsim`: each src/app/<command>.cpp makes its entry (name, help, options, what it
// runs), commands() lists them, and main.cpp only parses the command line and dispatches.
namespace rdsim {

struct Command {
  std::string name;  // "train"
  std::string help;  // one line for `rdsim --help`
  // Adds the command's options to `cmd` (the subcommand made for it) and returns what runs the
  // command once the command line is parsed: the process exit status.
  std::function<std::function<int()>(CLI::App& cmd)> add;
};

// Every command, in `rdsim --help` order.
std::vector<Command> commands();

// The first word of the command line when it names no command: rdsim::Error with the closest
// command ("did you mean") and the list. Options before a command other than --help/--version too.
void check_command_word(const std::vector<std::string>& names, int argc, char** argv);

// "rdsim: error: MESSAGE" on stderr (one line); returns 1.
int report_error(const std::string& message);
// Reports the exception being handled (call inside a catch): rdsim::Error and out of memory as
// errors (1), anything else as an internal error (70: a bug).
int report_current_exception();

// A command-line value that is a config value too (a seed), read by ConfigReader's rules, so
// "--seed -1" is an error naming `option`, never 2^64 - 1.
std::uint64_t seed_from_option(const std::string& text, const std::string& option);

// The benchmarks' `--json [FILE]`: also write the results as JSON to FILE, or to stdout ('-') when
// --json comes alone. Call resolve_json_option once the command line is parsed.
void add_json_option(CLI::App& cmd, std::string& path);
void resolve_json_option(const CLI::App& cmd, std::string& path);

// The entries, one per command file.
Command train_command_entry();
Command replay_command_entry();
Command bench_fps_command_entry();
Command bench_physics_command_entry();
Command render_command_entry();
Command envs_command_entry();
Command demos_command_entry();
Command config_reference_command_entry();
Command serve_command_entry();
Command keygen_command_entry();
Command bench_remote_command_entry();
Command bench_learner_command_entry();
Command teleop_command_entry();
Command dashboard_command_entry();
Command plot_command_entry();
Command urdf_command_entry();
Command export_command_entry();

}  // namespace rdsim
