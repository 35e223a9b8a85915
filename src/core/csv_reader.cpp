#include "rdsim/core/csv_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>

#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"

namespace rdsim {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

std::string_view trim_cr(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

// One data row, or false when it is malformed.
bool parse_row(std::string_view line, std::size_t width, std::vector<double>& out) {
  out.clear();
  std::size_t start = 0;
  for (std::size_t i = 0; i < width; ++i) {
    std::size_t end = line.find(',', start);
    const bool last = i + 1 == width;
    if (last != (end == std::string_view::npos)) return false;  // too few or too many cells
    if (last) end = line.size();
    const std::string_view cell = line.substr(start, end - start);
    if (cell.empty()) {
      out.push_back(std::numeric_limits<double>::quiet_NaN());
    } else {
      double v = 0;
      const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
      if (ec != std::errc() || ptr != cell.data() + cell.size()) return false;
      out.push_back(v);
    }
    start = end + 1;
  }
  return true;
}

}  // namespace

long long count_csv_rows(const std::string& path, long long at_most) {
  File file(::fdopen(InputFile(path, max_csv_log_bytes).release(), "rb"));
  if (!file) throw Error(path + ": cannot read: " + std::strerror(errno));
  long long lines = 0;
  for (int c; lines <= at_most && (c = std::fgetc(file.get())) != EOF;) lines += c == '\n';
  return std::max(lines - 1, 0LL);
}

int csv_column(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

CsvRows read_csv_rows(const std::string& path, std::uint64_t from, std::size_t max_bytes) {
  return read_csv_rows(InputFile(path, max_csv_log_bytes), from, max_bytes);
}

CsvRows read_csv_rows(InputFile input, std::uint64_t from, std::size_t max_bytes) {
  const std::string path = input.path();
  File file(::fdopen(input.fd(), "rb"));
  if (!file) throw Error(path + ": cannot read: " + std::strerror(errno));
  input.release();  // the FILE owns it now
  CsvRows out;

  // The header: the first line, when it is complete (read in pieces: it is usually short).
  std::string head;
  std::size_t head_end = std::string::npos;
  char piece[4096];
  while (head_end == std::string::npos && head.size() <= max_csv_line_bytes) {
    const std::size_t got = std::fread(piece, 1, sizeof piece, file.get());
    if (got == 0) break;
    head_end = std::string_view(piece, got).find('\n');
    if (head_end != std::string::npos) head_end += head.size();
    head.append(piece, got);
  }
  if (head_end == std::string::npos) {
    if (head.size() > max_csv_line_bytes) throw Error(path + ": the header line is longer than 64 KiB: not a CSV log");
    return out;  // the writer has not finished the header yet
  }
  for (std::string_view name : split(trim_cr(std::string_view(head).substr(0, head_end)))) {
    if (name.empty()) throw Error(path + ": the header has an empty column name: not a CSV log");
    out.columns.emplace_back(name);
  }
  if (out.columns.size() > max_csv_columns) throw Error(path + ": the header has more than 1024 columns");

  // The rows, from `from` on.
  const std::uint64_t first_row = head_end + 1;
  if (std::fseek(file.get(), 0, SEEK_END) != 0) throw Error(path + ": cannot seek: " + std::strerror(errno));
  const long size_now = std::ftell(file.get());
  const std::uint64_t size = size_now < 0 ? 0 : static_cast<std::uint64_t>(size_now);
  if (from > size) {
    out.restarted = true;
    from = first_row;
  }
  from = std::max(from, first_row);
  out.next = from;
  if (from >= size) return out;
  if (std::fseek(file.get(), static_cast<long>(from), SEEK_SET) != 0) throw Error(path + ": cannot seek");

  // Stream through the file: a line is kept while it is short enough to be a row, and a line too
  // long to be one is still followed to its end, so `next` always lands at the start of a line.
  std::string line;
  bool too_long = false;
  std::uint64_t at = from;  // offset of the next byte to consume
  std::vector<double> row;
  std::vector<char> chunk(64 * 1024);
  while (at < size) {
    const std::size_t got = std::fread(chunk.data(), 1, std::min<std::uint64_t>(chunk.size(), size - at), file.get());
    if (got == 0) break;
    std::size_t pos = 0;
    while (pos < got) {
      const char* nl = static_cast<const char*>(std::memchr(chunk.data() + pos, '\n', got - pos));
      const std::size_t end = nl ? static_cast<std::size_t>(nl - chunk.data()) : got;
      if (!too_long) {
        line.append(chunk.data() + pos, end - pos);
        if (line.size() > max_csv_line_bytes) {
          too_long = true;
          line.clear();
        }
      }
      at += end - pos + (nl ? 1 : 0);
      pos = end + (nl ? 1 : 0);
      if (!nl) break;
      if (too_long || !parse_row(trim_cr(line), out.columns.size(), row)) {
        ++out.skipped;
      } else {
        out.rows.push_back(row);
      }
      line.clear();
      too_long = false;
      out.next = at;
      if (out.next - from >= max_bytes) {
        out.more = out.next < size;
        return out;
      }
    }
  }
  return out;
}

}  // namespace rdsim
