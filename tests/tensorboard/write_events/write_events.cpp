// Test helper: writes a progress.csv's rows as TensorBoard scalars, as `rdsim train` does (one
// scalar per column, step = the row's timesteps), for test_event_accumulator.py.
//   write_events CSV DIR [--session-start STEP]
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/tensorboard/event_writer.hpp"

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::string(argv[3]) == "--session-start")) {
    std::fprintf(stderr, "usage: write_events CSV DIR [--session-start STEP]\n");
    return 2;
  }
  try {
    std::stringstream csv(rdsim::read_file(argv[1]));
    std::string line;
    std::getline(csv, line);
    const std::vector<std::string> columns = split(line);
    rdsim::EventWriter writer(argv[2]);
    if (argc == 5) writer.session_start(std::stoll(argv[4]));
    while (std::getline(csv, line)) {
      const std::vector<std::string> cells = split(line);
      writer.scalars(std::stoll(cells.at(0)), rdsim::scalars_of_row(columns, cells));
      writer.flush();
    }
    std::printf("%s\n", writer.path().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_events: %s\n", e.what());
    return 1;
  }
  return 0;
}
