#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "rdsim/core/csv_reader.hpp"
#include "rdsim/core/csv_writer.hpp"
#include "rdsim/core/error.hpp"
#include "../scratch_dir.hpp"

namespace {

std::string scratch(const std::string& name) {
  static const rdsim::test::ScratchDir root("csv_reader");  // removed when the test program exits
  return root / name;
}

void write(const std::string& path, const std::string& text, bool append = false) {
  std::ofstream out(path, append ? std::ios::app | std::ios::binary : std::ios::trunc | std::ios::binary);
  out << text;
}

}  // namespace

TEST_CASE("CSV reader returns what CsvWriter wrote, empty cells as NaN", "[csv]") {
  const std::string path = scratch("written.csv");
  {
    rdsim::CsvWriter w(path, {"timesteps", "mean_return", "success_rate"});
    w.write_row({rdsim::CsvWriter::cell(100LL), rdsim::CsvWriter::cell(-3.25), rdsim::CsvWriter::cell(std::nan(""))});
    w.write_row({rdsim::CsvWriter::cell(200LL), rdsim::CsvWriter::cell(1.5e-7), rdsim::CsvWriter::cell(0.5)});
  }
  const rdsim::CsvRows r = rdsim::read_csv_rows(path);
  REQUIRE(r.columns == std::vector<std::string>{"timesteps", "mean_return", "success_rate"});
  REQUIRE(r.rows.size() == 2);
  CHECK(r.rows[0][0] == 100);
  CHECK(r.rows[0][1] == -3.25);
  CHECK(std::isnan(r.rows[0][2]));
  CHECK(r.rows[1][1] == 1.5e-7);
  CHECK(r.skipped == 0);
  CHECK_FALSE(r.more);
  CHECK(r.next == std::filesystem::file_size(path));
  CHECK(rdsim::csv_column(r.columns, "success_rate") == 2);
  CHECK(rdsim::csv_column(r.columns, "loss") == -1);
}

TEST_CASE("CSV reader follows a growing file and leaves a half-written row for later", "[csv]") {
  const std::string path = scratch("growing.csv");
  write(path, "t,v\n1,10\n2,2");  // the writer is in the middle of row 2
  rdsim::CsvRows r = rdsim::read_csv_rows(path);
  REQUIRE(r.rows.size() == 1);
  CHECK(r.rows[0] == std::vector<double>{1, 10});
  write(path, "0\n3,30\n", true);
  r = rdsim::read_csv_rows(path, r.next);
  REQUIRE(r.rows.size() == 2);
  CHECK(r.rows[0] == std::vector<double>{2, 20});  // completed, read once, in full
  CHECK(r.rows[1] == std::vector<double>{3, 30});
  const std::uint64_t end = r.next;
  r = rdsim::read_csv_rows(path, end);
  CHECK(r.rows.empty());
  CHECK(r.next == end);
}

TEST_CASE("CSV reader skips malformed rows and keeps going", "[csv]") {
  const std::string path = scratch("malformed.csv");
  write(path, std::string("t,v\n1,10\n2\n3,30,7\nfour,40\n5,5x\n\n6,\xff\n") + std::string("7,\0,\n", 5) +
                  "8,80\r\n9,9e400\n10,100\n");
  const rdsim::CsvRows r = rdsim::read_csv_rows(path);
  REQUIRE(r.rows.size() == 3);
  CHECK(r.rows[0] == std::vector<double>{1, 10});
  CHECK(r.rows[1] == std::vector<double>{8, 80});  // a Windows line ending is fine
  CHECK(r.rows[2] == std::vector<double>{10, 100});
  CHECK(r.skipped == 8);  // too few, too many, not numbers, empty line, bytes, NUL, out of range
}

TEST_CASE("CSV reader steps over a line too long to be a row without holding it", "[csv]") {
  const std::string path = scratch("long.csv");
  write(path, "t,v\n1,10\n" + std::string(3 * rdsim::max_csv_line_bytes, '7') + "\n2,20\n");
  const rdsim::CsvRows r = rdsim::read_csv_rows(path);
  REQUIRE(r.rows.size() == 2);
  CHECK(r.rows[1] == std::vector<double>{2, 20});
  CHECK(r.skipped == 1);
}

TEST_CASE("CSV reader answers in pieces of about max_bytes", "[csv]") {
  const std::string path = scratch("pieces.csv");
  std::string text = "t,v\n";
  for (int i = 0; i < 1000; ++i) text += std::to_string(i) + "," + std::to_string(2 * i) + "\n";
  write(path, text);
  std::uint64_t from = 0;
  std::vector<double> ts;
  int answers = 0;
  for (bool more = true; more; ++answers) {
    const rdsim::CsvRows r = rdsim::read_csv_rows(path, from, 1000);
    for (const auto& row : r.rows) ts.push_back(row[0]);
    more = r.more;
    from = r.next;
    REQUIRE(answers < 100);
  }
  CHECK(answers > 5);
  REQUIRE(ts.size() == 1000);
  for (int i = 0; i < 1000; ++i) CHECK(ts[static_cast<std::size_t>(i)] == i);
}

TEST_CASE("CSV reader starts over when the file was rewritten shorter", "[csv]") {
  const std::string path = scratch("rewritten.csv");
  write(path, "t,v\n1,10\n2,20\n3,30\n");
  const std::uint64_t end = rdsim::read_csv_rows(path).next;
  write(path, "t,v\n1,10\n");  // a resumed run keeps the rows its checkpoint knows
  const rdsim::CsvRows r = rdsim::read_csv_rows(path, end);
  CHECK(r.restarted);
  REQUIRE(r.rows.size() == 1);
}

TEST_CASE("CSV reader: no header yet is no rows, a file that is not a CSV log is an error", "[csv]") {
  const std::string path = scratch("header.csv");
  write(path, "timesteps,mean_re");
  CHECK(rdsim::read_csv_rows(path).columns.empty());
  write(path, "a,,b\n1,2,3\n");
  CHECK_THROWS_WITH(rdsim::read_csv_rows(path), Catch::Contains("empty column name"));
  write(path, std::string(rdsim::max_csv_line_bytes + 10, 'x'));
  CHECK_THROWS_WITH(rdsim::read_csv_rows(path), Catch::Contains("longer than 64 KiB"));
  CHECK_THROWS_AS(rdsim::read_csv_rows(scratch("missing.csv")), rdsim::Error);
}
