#pragma once
#include <cstdint>
#include <string>
#include <vector>

// Reads the numeric CSV logs of a run (progress.csv, episodes.csv; see CsvWriter) while they may
// still be growing. Only complete lines (ending in '\n') are read, from a byte offset on, so a
// reader follows a live file by asking again from `next`: a half-written last row is left for
// the next call. A row that does not parse (wrong number of cells, a cell that is not a number, a
// line longer than max_line_bytes) is skipped and counted, never fatal.
namespace rdsim {

class InputFile;

struct CsvRows {
  std::vector<std::string> columns;       // the header; empty while the file has no complete header
  std::vector<std::vector<double>> rows;  // one value per column; NaN for an empty cell
  std::uint64_t next = 0;                 // byte offset just after the last complete line read
  long long skipped = 0;                  // malformed rows dropped in this read
  bool restarted = false;                 // `from` lay past the end (the file was rewritten): read from the top
  bool more = false;                      // stopped at max_bytes: ask again from `next`
};

inline constexpr std::size_t max_csv_line_bytes = 64 * 1024;
inline constexpr std::size_t max_csv_columns = 1024;
// The largest log rdsim opens (a log is read in pieces of at most max_bytes; see input_file.hpp).
inline constexpr std::uint64_t max_csv_log_bytes = 64ull << 30;

// Reads the rows that start at byte `from` or later (from <= the header's end: the first row), at
// most about max_bytes of them. Throws rdsim::Error naming the file when it cannot be opened or its
// header is not a CSV header (an empty column name, too many columns, a line too long).
CsvRows read_csv_rows(const std::string& path, std::uint64_t from = 0, std::size_t max_bytes = 64 * 1024 * 1024);
// The same from a file already opened (InputFile::beneath: the dashboard's run files).
CsvRows read_csv_rows(InputFile file, std::uint64_t from, std::size_t max_bytes);

// The rows after the header line (complete lines), counting at most at_most + 1 of them.
// rdsim::Error naming the file when it cannot be read or is not a regular file.
long long count_csv_rows(const std::string& path, long long at_most);

// The column's index in `columns`, or -1.
int csv_column(const std::vector<std::string>& columns, const std::string& name);

}  // namespace rdsim
