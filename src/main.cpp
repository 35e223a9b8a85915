// rdsim: one binary for training, replaying and benchmarking robot learning. The commands are
// src/app/<command>.cpp (the table: rdsim/app/command.hpp); this parses the line and dispatches.
//
// Exit status: 0 success; 1 any error (bad input, bad command line, out of memory), reported as
// one line "rdsim: error: ..."; 130 / 143 a training run stopped by SIGINT / SIGTERM after saving
// its checkpoint (`rdsim train --resume DIR` continues it); 70 an internal error (a bug: please
// report it).
#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "rdsim/app/command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"rdsim " RDSIM_VERSION " - robot deep reinforcement learning simulator\n"
               "Exit status: 0 done, 1 error (one line \"rdsim: error: ...\"), 130/143 training stopped by "
               "SIGINT/SIGTERM after saving (continue with train --resume), 70 internal error"};
  app.require_subcommand(1);
  app.set_version_flag("--version", RDSIM_VERSION);

  std::vector<std::string> names;
  std::map<std::string, std::function<int()>> runs;
  for (const rdsim::Command& command : rdsim::commands()) {
    names.push_back(command.name);
    runs[command.name] = command.add(*app.add_subcommand(command.name, command.help));
  }
  try {
    rdsim::check_command_word(names, argc, argv);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
      // The command the error is about: "rdsim demos record --help", not its parent's help.
      std::string command = "rdsim";
      for (const CLI::App* at = &app; !at->get_subcommands().empty();) {
        at = at->get_subcommands().front();
        command += " " + at->get_name();
      }
      return rdsim::report_error(std::string(e.what()) + " (" + command + " --help)");
    }
    return runs.at(app.get_subcommands().front()->get_name())();
  } catch (...) {
    return rdsim::report_current_exception();
  }
}
