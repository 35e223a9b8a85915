#pragma once
// Helpers for the train/replay tests: scratch folders and running the real binary.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "../leak_check_env.hpp"
#ifdef RDSIM_BINARY
#include <catch2/catch.hpp>

#include "rdsim/training/model_file.hpp"
#endif
#include "../scratch_dir.hpp"

namespace rltest {

// A fresh folder rdsim_rl_<tag>_<pid> under the system temp dir, removed when the object goes away.
struct ScratchDir : rdsim::test::ScratchDir {
  explicit ScratchDir(const std::string& tag) : rdsim::test::ScratchDir("rl_" + tag) {}
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

inline void spit(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `<program> <args>` with stdout/stderr captured in files of `dir`.
inline RunResult run_captured(const std::string& program, const std::string& args, const ScratchDir& dir) {
  const std::string out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = program + " " + args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

#ifdef RDSIM_BINARY  // the app tests (tests/CMakeLists.txt); the training tests drive the library only
// Runs `rdsim <args>`.
inline RunResult run_rdsim(const std::string& args, const ScratchDir& dir) { return run_captured(RDSIM_BINARY, args, dir); }
#endif

#ifdef RDSIM_MPIEXEC
// Runs `mpirun -np <ranks> rdsim <args>` (oversubscribed: CI has 2 cores; CI runs as root, which
// Open MPI refuses unless told).
inline RunResult run_rdsim_mpi(int ranks, const std::string& args, const ScratchDir& dir) {
  return run_captured(std::string(no_leak_check_env) + "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + std::string(RDSIM_MPIEXEC) +
                          " -np " + std::to_string(ranks) + " --oversubscribe " + RDSIM_BINARY,
                      args, dir);
}

// `mpirun -np 2 rdsim train --quiet --config CONFIG` twice, into DIR/a and DIR/b: both must run as
// 2-rank jobs (the caller compares what they wrote).
inline void train_twice_on_two_ranks(const std::string& config, const ScratchDir& dir) {
  for (const char* name : {"a", "b"}) {
    const auto r = run_rdsim_mpi(2, "train --quiet --config " + config + " --log-dir " + (dir / name), dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.out, Catch::Matchers::Contains("2 MPI ranks"));
  }
}
#endif

inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
}

// The CSV text with the last `drop` columns of every line removed.
inline std::string drop_columns(const std::string& csv, int drop) {
  std::string result;
  for (const auto& line : lines(csv)) {
    std::string kept = line;
    for (int k = 0; k < drop; ++k) kept = kept.substr(0, kept.rfind(','));
    result += kept + "\n";
  }
  return result;
}

#ifdef RDSIM_BINARY
// What two runs that should be the same must share: the CSVs without their wall-clock columns,
// and the weights.
struct RunLogs {
  std::string progress, episodes, weights;
  bool operator==(const RunLogs&) const = default;
};
inline RunLogs run_logs(const std::string& run) {
  return {drop_columns(slurp(run + "/progress.csv"), 2), drop_columns(slurp(run + "/episodes.csv"), 1),
          rdsim::read_model_file(run + "/model.bin").payload};
}

// Each config text of `cases` is refused by `rdsim train` with exit status 1 and one line naming
// the config file and holding the case's reason.
inline void check_config_errors(const ScratchDir& dir, const std::vector<std::pair<std::string, std::string>>& cases) {
  for (const auto& [text, why] : cases) {
    const std::string path = dir / "bad.json";
    spit(path, text);
    const auto r = run_rdsim("train --config " + path + " --log-dir " + (dir / "run"), dir);
    INFO(text << "\n" << r.err);
    CHECK(r.exit_code == 1);
    CHECK(lines(r.err).size() == 1);
    CHECK_THAT(r.err, Catch::Matchers::Contains(path) && Catch::Matchers::Contains(why));
  }
}
#endif

}  // namespace rltest
