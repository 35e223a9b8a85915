#include <catch2/catch.hpp>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <string>
#include <thread>
#include <unistd.h>
#include <utility>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/input_file.hpp"
#include "../finishes_within.hpp"

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
  // A device is not read at all (input_file.hpp), endless or not.
  CHECK_THROWS_WITH(rdsim::read_file("/dev/zero", 1 << 20), Catch::Matchers::Contains("/dev/zero") &&
                                                               Catch::Matchers::Contains("is not a regular file (it is a character device)"));
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

TEST_CASE("only regular files are read: FIFOs, devices and sockets are refused at once", "[files]") {
  fs::path dir = fs::temp_directory_path() / ("rdsim_test_files_special_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string fifo = (dir / "x.fifo").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string sock = (dir / "x.sock").string();
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock.c_str());
  REQUIRE(::bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  using namespace std::chrono_literals;
  for (const auto& [path, kind] : std::vector<std::pair<std::string, std::string>>{
           {fifo, "a FIFO"}, {"/dev/urandom", "a character device"}, {"/dev/null", "a character device"}, {sock, "a socket"}}) {
    INFO(path);
    const std::string& file = path;  // a structured binding cannot be captured before C++20's P1091 (clang 14)
    // Before: opening the FIFO waited for a writer for ever; /dev/urandom was read without end.
    const auto r = rdsim::test::finishes_within(5s, [&] { rdsim::read_file(file, 1 << 20); });
    CHECK(r.in_time);
    CHECK_THAT(r.message, Catch::Matchers::Contains(path + ": is not a regular file (it is " + kind));
  }
  ::close(s);
  fs::remove_all(dir);
}

TEST_CASE("a file opened below a folder never leaves it through a link", "[files]") {
  fs::path dir = fs::temp_directory_path() / ("rdsim_test_files_beneath_" + std::to_string(::getpid()));
  fs::create_directories(dir / "root" / "run");
  rdsim::write_file_atomic((dir / "root" / "run" / "log.csv").string(), "inside");
  rdsim::write_file_atomic((dir / "secret.csv").string(), "outside");
  fs::create_symlink("log.csv", dir / "root" / "run" / "near.csv");         // stays inside: followed
  fs::create_symlink(dir / "secret.csv", dir / "root" / "run" / "far.csv");   // leads out: refused
  fs::create_symlink("../../secret.csv", dir / "root" / "run" / "up.csv");    // leads out: refused
  fs::create_directory_symlink(dir, dir / "root" / "out");                    // a folder out: refused
  const std::string root = (dir / "root").string();
  CHECK(rdsim::InputFile::beneath(root, "run/log.csv", 100).read_rest() == "inside");
  CHECK(rdsim::InputFile::beneath(root, "run/near.csv", 100).read_rest() == "inside");
  for (const char* out : {"run/far.csv", "run/up.csv", "out/secret.csv", "../secret.csv", "/etc/passwd"}) {
    INFO(out);
    try {
      rdsim::InputFile::beneath(root, out, 100);
      FAIL("opened");
    } catch (const rdsim::FileOpenError& e) {
      CHECK(e.link_out());
    }
  }
  try {
    rdsim::InputFile::beneath(root, "run/missing.csv", 100);
    FAIL("opened");
  } catch (const rdsim::FileOpenError& e) {
    CHECK(e.code() == ENOENT);
  }
  CHECK_THROWS_WITH(rdsim::InputFile::beneath(root, "run/log.csv", 3), Catch::Matchers::Contains("is 6 bytes, more than the 3 bytes"));
  fs::remove_all(dir);
}
