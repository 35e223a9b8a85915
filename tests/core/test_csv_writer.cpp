#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "../scratch_dir.hpp"

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::string scratch(const std::string& name) {
  static const rdsim::test::ScratchDir root("csv");  // removed when the test program exits
  return root / name;
}

}  // namespace

TEST_CASE("CSV rows are on disk as soon as they are written", "[csv]") {
  const std::string path = scratch("rows.csv");
  rdsim::CsvWriter w(path, {"a", "b"});
  CHECK(read_text(path) == "a,b\n");
  w.write_row({rdsim::CsvWriter::cell(1LL), rdsim::CsvWriter::cell(0.5)});
  CHECK(read_text(path) == "a,b\n1,0.5\n");  // flushed: readable while the writer is open
  CHECK(w.rows() == 1);
  CHECK_THROWS_AS(w.write_row({"1"}), rdsim::Error);
  CHECK(rdsim::CsvWriter::cell(std::nan("")) == "");
  CHECK(rdsim::CsvWriter::cell(true) == "1");
  CHECK(std::stod(rdsim::CsvWriter::cell(0.1f)) == Approx(0.1f));
  CHECK(static_cast<float>(std::stod(rdsim::CsvWriter::cell(static_cast<double>(0.1f))))== 0.1f);
}

TEST_CASE("resuming a CSV keeps the rows a checkpoint knows about", "[csv]") {
  const std::string path = scratch("resume.csv");
  {
    rdsim::CsvWriter w(path, {"x"});
    for (int i = 0; i < 5; ++i) w.write_row({std::to_string(i)});
  }
  {
    rdsim::CsvWriter w(path, {"x"}, 3);
    CHECK(w.rows() == 3);
    w.write_row({"new"});
  }
  CHECK(read_text(path) == "x\n0\n1\n2\nnew\n");
  CHECK_THROWS_AS(rdsim::CsvWriter(path, {"y"}, 1), rdsim::Error);   // other columns
  CHECK_THROWS_AS(rdsim::CsvWriter(path, {"x"}, 10), rdsim::Error);  // fewer rows than recorded
  CHECK_THROWS_AS(rdsim::CsvWriter(scratch("missing.csv"), {"x"}, 2), rdsim::Error);
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}
