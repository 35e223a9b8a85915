#include <catch2/catch.hpp>
#include <filesystem>

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
  fs::remove_all(dir);
}

TEST_CASE("file errors name the file", "[files]") {
  CHECK_THROWS_WITH(rdsim::read_file("/nonexistent/rdsim.bin"), Catch::Matchers::Contains("/nonexistent/rdsim.bin"));
  CHECK_THROWS_AS(rdsim::write_file_atomic("/nonexistent/dir/x.bin", "x"), rdsim::Error);
}
