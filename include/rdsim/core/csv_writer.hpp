#pragma once
#include <cstdio>
#include <string>
#include <vector>

// A CSV log that survives crashes: every row is flushed as it is written. Resuming a run keeps
// the rows a checkpoint knows about and drops the ones written after it, so the file always
// matches the state training continues from.
namespace rdsim {

class CsvWriter {
public:
  // keep_rows < 0: start a new file with the header. keep_rows >= 0: the file must exist with
  // the same header; its first keep_rows data rows are kept, the rest removed, and new rows are
  // appended. Throws rdsim::Error naming the file on any problem.
  CsvWriter(const std::string& path, std::vector<std::string> columns, long long keep_rows = -1);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  // One row, exactly one cell per column (use cell() to format numbers); flushed at once.
  void write_row(const std::vector<std::string>& cells);

  long long rows() const { return rows_; }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::string& path() const { return path_; }

  // Numbers formatted so that they read back exactly (doubles with 17 significant digits
  // would be noisy; 9 is exact for the floats the networks produce and plenty for statistics).
  static std::string cell(double value);
  static std::string cell(long long value);
  static std::string cell(int value) { return cell(static_cast<long long>(value)); }
  static std::string cell(bool value) { return value ? "1" : "0"; }

private:
  std::string path_;
  std::vector<std::string> columns_;
  std::FILE* file_ = nullptr;
  long long rows_ = 0;
};

}  // namespace rdsim
