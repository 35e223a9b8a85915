#include "rdsim/core/csv_writer.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "rdsim/core/csv_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace rdsim {
namespace {

std::string join(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) line += (i ? "," : "") + cells[i];
  return line;
}

}  // namespace

CsvWriter::CsvWriter(const std::string& path, std::vector<std::string> columns, long long keep_rows)
    : path_(path), columns_(std::move(columns)) {
  const std::string header = join(columns_) + "\n";
  std::string kept = header;
  std::error_code ec;
  if (keep_rows > 0 || (keep_rows == 0 && std::filesystem::exists(path, ec))) {
    if (!std::filesystem::exists(path, ec)) throw Error(path + ": cannot resume: the file is missing");
    // The kept rows are rewritten whole below, so the file is read whole: a regular file only.
    std::istringstream in(read_file(path, max_csv_log_bytes));
    std::string line;
    if (!std::getline(in, line) || line + "\n" != header) {
      throw Error(path + ": cannot resume: its header differs from this run's columns");
    }
    for (long long i = 0; i < keep_rows; ++i) {
      if (!std::getline(in, line)) {
        throw Error(path + ": cannot resume: it has fewer rows than the checkpoint recorded (" +
                    std::to_string(keep_rows) + ")");
      }
      kept += line + "\n";
    }
    rows_ = keep_rows;
  }
  // Rewrite what we keep atomically, then append: a crash in between loses no kept row.
  write_file_atomic(path, kept);
  file_ = std::fopen(path.c_str(), "a");
  if (!file_) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
}

CsvWriter::~CsvWriter() {
  if (file_) std::fclose(file_);
}

void CsvWriter::write_row(const std::vector<std::string>& cells) {
  if (cells.size() != columns_.size()) {
    throw Error(path_ + ": row has " + std::to_string(cells.size()) + " cells for " + std::to_string(columns_.size()) +
                " columns");
  }
  const std::string line = join(cells) + "\n";
  if (std::fwrite(line.data(), 1, line.size(), file_) != line.size() || std::fflush(file_) != 0) {
    throw Error(path_ + ": cannot write: " + std::strerror(errno));
  }
  ++rows_;
}

std::string CsvWriter::cell(double value) {
  if (std::isnan(value)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", value);
  return buf;
}

std::string CsvWriter::cell(long long value) { return std::to_string(value); }

}  // namespace rdsim
