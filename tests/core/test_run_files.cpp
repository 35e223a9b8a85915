#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include "rdsim/core/error.hpp"
#include "rdsim/core/run_files.hpp"
#include "../scratch_dir.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch_dir(const std::string& name) {
  static const rdsim::test::ScratchDir root("run_files");  // removed when the test program exits
  const fs::path dir = root.path / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void touch(const fs::path& file, const std::string& text = "t\n") {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

}  // namespace

TEST_CASE("run info comes from config.json and tolerates a missing or broken one", "[runs]") {
  const fs::path dir = scratch_dir("info");
  touch(dir / "config.json", R"({"algorithm": "ppo", "env": {"name": "jaka_button"}, "seed": 3})");
  rdsim::RunInfo info = rdsim::read_run_info(dir.string());
  CHECK(info.algorithm == "ppo");
  CHECK(info.env == "jaka_button");
  REQUIRE(info.seed);
  CHECK(*info.seed == 3);
  touch(dir / "config.json", R"({"algorithm": 7, "env": "x", "seed": -1)");  // unfinished JSON
  info = rdsim::read_run_info(dir.string());
  CHECK(info.algorithm.empty());
  CHECK_FALSE(info.seed);
  fs::remove(dir / "config.json");
  CHECK(rdsim::read_run_info(dir.string()).env.empty());
}

TEST_CASE("run folders are the folders holding progress.csv, links not followed", "[runs]") {
  const fs::path root = scratch_dir("find");
  touch(root / "a" / "seed1" / "progress.csv");
  touch(root / "a" / "seed2" / "progress.csv");
  touch(root / "b" / "episodes.csv");  // no progress.csv: not a run
  touch(root / "1" / "2" / "3" / "4" / "5" / "progress.csv");  // deeper than max_depth
  const fs::path outside = scratch_dir("outside");
  touch(outside / "secret" / "progress.csv");
  fs::create_directory_symlink(outside / "secret", root / "link");
  const auto runs = rdsim::find_run_folders(root.string());
  REQUIRE(runs.size() == 2);
  CHECK(runs[0] == (root / "a" / "seed1").string());
  CHECK(runs[1] == (root / "a" / "seed2").string());
  CHECK(rdsim::find_run_folders((root / "a" / "seed1").string()).size() == 1);  // a run folder itself
  CHECK(rdsim::find_run_folders(root.string(), 4, 1).size() == 1);
  CHECK_THROWS_AS(rdsim::find_run_folders((root / "nothing").string()), rdsim::Error);
}

TEST_CASE("run info below a root: a FIFO or a link out of the root gives an empty info at once", "[runs]") {
  const fs::path base = scratch_dir("info_beneath");
  touch(base / "root" / "good" / "config.json", R"({"algorithm": "ppo", "seed": 3})");
  touch(base / "outside.json", R"({"algorithm": "secret"})");
  fs::create_directories(base / "root" / "linked");
  fs::create_symlink(base / "outside.json", base / "root" / "linked" / "config.json");
  fs::create_directories(base / "root" / "fifo");
  REQUIRE(::mkfifo((base / "root" / "fifo" / "config.json").c_str(), 0600) == 0);
  const std::string root = (base / "root").string();
  CHECK(rdsim::read_run_info_beneath(root, "good").algorithm == "ppo");
  CHECK(rdsim::read_run_info_beneath(root, "linked").algorithm.empty());  // never read through the link
  CHECK(rdsim::read_run_info_beneath(root, "fifo").algorithm.empty());    // before: blocked in the open
  CHECK(rdsim::read_run_info((base / "root" / "fifo").string()).algorithm.empty());
}
