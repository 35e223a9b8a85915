#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace fs = std::filesystem;

TEST_CASE("atomic write replaces the file and leaves no temporary behind", "[files]") {
  fs::path dir = fs::temp_directory_path() / "rdsim_test_files";
  fs::create_directories(dir);
  std::string path = (dir / "out.bin").string();
  rdsim::write_file_atomic(path, "first");
  rdsim::write_file_atomic(path, std::string("sec\0nd", 6));
  CHECK(rdsim::read_file(path) == std::string("sec\0nd", 6));
  CHECK_FALSE(fs::exists(path + ".tmp"));
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename() == "out.bin");  // no temporaries
  fs::remove_all(dir);
}

TEST_CASE("file errors name the file", "[files]") {
  CHECK_THROWS_WITH(rdsim::read_file("/nonexistent/rdsim.bin"), Catch::Matchers::Contains("/nonexistent/rdsim.bin"));
  CHECK_THROWS_AS(rdsim::write_file_atomic("/proc/rdsim/x.bin", "x"), rdsim::Error);  // /proc takes no folders
}

TEST_CASE("atomic write creates the missing folders above the file (demos/x.demo on a clean clone)", "[files]") {
  const fs::path dir = fs::temp_directory_path() / ("rdsim_test_files_parents_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string path = (dir / "demos" / "deeper" / "x.demo").string();
  rdsim::write_file_atomic(path, "bytes");
  CHECK(rdsim::read_file(path) == "bytes");
  // A file where a folder must go: one clear error naming the file and the folder.
  rdsim::write_file_atomic((dir / "plain").string(), "x");
  CHECK_THROWS_WITH(rdsim::write_file_atomic((dir / "plain" / "y.csv").string(), "y"),
                    Catch::Matchers::Contains("y.csv: cannot create its folder") &&
                        Catch::Matchers::Contains("plain"));
  fs::remove_all(dir);
}

TEST_CASE("atomic writes from several writers never mix: each reader sees one whole file", "[files]") {
  fs::path dir = fs::temp_directory_path() / ("rdsim_test_files_race_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "shared.bin").string();
  std::vector<std::thread> writers;
  for (char c : {'a', 'b', 'c', 'd'})
    writers.emplace_back([&, c] {
      for (int i = 0; i < 50; ++i) rdsim::write_file_atomic(path, std::string(100000, c));
    });
  int whole = 0, reads = 0;
  for (int i = 0; i < 200; ++i) {
    if (!fs::exists(path)) continue;  // not written yet
    const std::string seen = rdsim::read_file(path);
    ++reads;
    whole += seen.size() == 100000 && seen.find_first_not_of(seen[0]) == std::string::npos;
  }
  for (auto& w : writers) w.join();
  CHECK(whole == reads);
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename() == "shared.bin");
  fs::remove_all(dir);
}

TEST_CASE("reads are bounded: a file larger than the limit, or endless, is refused", "[files]") {
  CHECK_THROWS_WITH(rdsim::read_file("/dev/zero", 1 << 20), Catch::Matchers::Contains("/dev/zero") &&
                                                               Catch::Matchers::Contains("holds more than the 1048576 bytes"));
  fs::path dir = fs::temp_directory_path() / ("rdsim_test_files_big_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  rdsim::write_file_atomic((dir / "big").string(), std::string(1000, 'x'));
  CHECK_THROWS_WITH(rdsim::read_file((dir / "big").string(), 999), Catch::Matchers::Contains("is 1000 bytes"));
  CHECK(rdsim::read_file((dir / "big").string(), 1000).size() == 1000);
  CHECK_THROWS_WITH(rdsim::read_file(dir.string()), Catch::Matchers::Contains("is a folder"));
  fs::remove_all(dir);
}

TEST_CASE("leftovers of a killed atomic write are recognised by name", "[files]") {
  CHECK(rdsim::is_atomic_write_leftover(".model.bin.a1B2c3.tmp"));
  CHECK_FALSE(rdsim::is_atomic_write_leftover("model.bin"));
  CHECK_FALSE(rdsim::is_atomic_write_leftover(".rdsim.lock"));
  CHECK_FALSE(rdsim::is_atomic_write_leftover("notes.tmp"));
}

TEST_CASE("a missing file another command makes: the error says how to make it", "[files]") {
  CHECK_THROWS_WITH(rdsim::read_file_or_hint("/nonexistent/k.key", "rdsim keygen k"),
                    Catch::Matchers::Equals("/nonexistent/k.key: cannot open: No such file or directory; make it with: rdsim keygen k"));
  CHECK_THROWS_WITH(rdsim::read_file_or_hint("/", "x"), Catch::Matchers::Contains("is a folder"));  // other errors unchanged
}
