#include "rdsim/app/command.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <nlohmann/json.hpp>

#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/suggest.hpp"

namespace rdsim {
std::vector<Command> commands() {
  return {train_command_entry(),     replay_command_entry(), bench_fps_command_entry(),
          bench_physics_command_entry(),
          render_command_entry(),    envs_command_entry(),   demos_command_entry(),
          config_reference_command_entry(), serve_command_entry(), keygen_command_entry(),
          bench_remote_command_entry(), bench_learner_command_entry(), teleop_command_entry(), dashboard_command_entry(),
          plot_command_entry(), urdf_command_entry(), export_command_entry()};
}

void check_command_word(const std::vector<std::string>& names, int argc, char** argv) {
  if (argc < 2) return;  // CLI11 says a command is required
  const std::string word = argv[1];
  if (word[0] == '-') {
    if (word == "-h" || word == "--help" || word == "--version") return;
    throw Error("unknown option \"" + one_line(word, 40) + "\" before the command (rdsim --help)");
  }
  if (std::find(names.begin(), names.end(), word) != names.end()) return;
  // A command the word begins ("bench" -> "bench-fps"), else the fewest edits away (core/suggest.hpp).
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  throw Error("unknown command \"" + one_line(word, 40) + "\"" + did_you_mean(word, names) + "; commands: " + list +
              " (rdsim --help)");
}

int report_error(const std::string& message) {
  std::fprintf(stderr, "rdsim: error: %s\n", one_line(message, 2000).c_str());
  return 1;
}

int report_current_exception() {
  try {
    throw;
  } catch (const Error& e) {
    return report_error(e.what());
  } catch (const std::bad_alloc&) {
    return report_error("out of memory: the machine (or ulimit -v) could not provide what this command needs; "
                        "use smaller sizes or lower --max-memory so the run is refused up front");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rdsim: internal error: %s\n", one_line(e.what(), 2000).c_str());
    return 70;
  }
}

std::uint64_t seed_from_option(const std::string& text, const std::string& option) {
  nlohmann::json j = nlohmann::json::object();
  j["seed"] = json_from_option(text);
  ConfigReader r(j, option);
  std::uint64_t seed = 0;
  r.read("seed", seed);
  return seed;
}

void add_json_option(CLI::App& cmd, std::string& path) {
  cmd.add_option("--json", path,
                 "Also write the results as JSON to FILE; --json alone or '-': to stdout (the table then goes to stderr)")
      ->expected(0, 1)
      ->type_name("[FILE]");
}

void resolve_json_option(const CLI::App& cmd, std::string& path) {
  if (cmd.count("--json") && path.empty()) path = "-";
}

}  // namespace rdsim
