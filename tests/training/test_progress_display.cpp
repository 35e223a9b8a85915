#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "rdsim/training/progress_display.hpp"

namespace {

std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string text;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) text.append(buf, n);
  return text;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t at; (at = text.find(sep, start)) != std::string::npos; start = at + 1) {
    parts.push_back(text.substr(start, at - start));
  }
  parts.push_back(text.substr(start));
  return parts;
}

int percent_in(const std::string& line) {
  const auto pct = line.find('%');
  REQUIRE(pct != std::string::npos);
  auto start = pct;
  while (start > 0 && (std::isdigit(static_cast<unsigned char>(line[start - 1])) != 0)) --start;
  return std::stoi(line.substr(start, pct - start));
}

}  // namespace

TEST_CASE("progress on a terminal: a bar rewritten in place that ends at exactly 100%", "[progress]") {
  std::FILE* f = std::tmpfile();
  rdsim::ProgressDisplay display(false, f, true);
  rdsim::EpisodeStats stats;
  const long long total = 300000;
  // Updates of 2,048 steps overshoot the total, as a rollout does.
  long long t = 0;
  for (double wall = 0; t < total; wall += 0.05) {
    t += 2048;
    if (t > 100000) {
      stats.count = 100;
      stats.success_rate = 0.9;
      stats.mean_return = -12.34;
    }
    display.show(t, total, stats, 8000, wall);
  }
  display.show(t, total, stats, 8000, 100, true);
  display.finish();
  const std::string text = contents(f);
  std::fclose(f);
  REQUIRE(text.back() == '\n');
  std::vector<std::string> lines = split(text.substr(0, text.size() - 1), '\r');
  lines.erase(lines.begin());  // before the first \r
  REQUIRE(lines.size() > 10);
  REQUIRE(lines.size() < 100);  // at most ten a second
  int last = -1;
  for (const auto& line : lines) {
    INFO(line);
    CHECK(line.size() <= 79 + 3);  // the terminal's 80 columns, less one, and "\x1b[K"
    const int p = percent_in(line);
    CHECK(p >= last);
    CHECK(p <= 100);
    if (p < 100) CHECK(line.find("100%") == std::string::npos);
    last = p;
  }
  const std::string& end = lines.back();
  CHECK(percent_in(end) == 100);
  const auto close = end.find(']');
  REQUIRE(close != std::string::npos);
  CHECK(end[0] == '[');
  CHECK(end.substr(1, close - 1).find_first_not_of('#') == std::string::npos);  // a full bar
  CHECK(end.find("301056/300000 steps") != std::string::npos);
  CHECK(end.find("success 0.90") != std::string::npos);
  CHECK(end.find("return") == std::string::npos);  // 80 columns: no room for it beside the bar
  CHECK(rdsim::ProgressDisplay::terminal_line(t, total, stats, 8000, 120).find("return -12.3") != std::string::npos);
  CHECK(end.find("8000 steps/s") != std::string::npos);
  CHECK(end.find("ETA 0:00") != std::string::npos);
}

TEST_CASE("progress line: rounded down, fitted to the width, ETA in minutes", "[progress]") {
  rdsim::EpisodeStats none;
  const std::string early = rdsim::ProgressDisplay::terminal_line(2999, 3000, none, 10, 120);
  CHECK(early.find(" 99%") != std::string::npos);
  CHECK(early.find("success -") != std::string::npos);
  CHECK(early.find("ETA 0:00") != std::string::npos);
  CHECK(rdsim::ProgressDisplay::terminal_line(0, 3000, none, 0, 120).find("[....") == 0);
  CHECK(rdsim::ProgressDisplay::terminal_line(1000, 100000, none, 10, 120).find("ETA 2:45:00") != std::string::npos);
  const std::string narrow = rdsim::ProgressDisplay::terminal_line(50, 100, none, 10, 40);
  CHECK(narrow.size() <= 39);
  CHECK(narrow.find('[') == std::string::npos);  // no room for a bar
}

TEST_CASE("progress off a terminal: plain lines every 10 s and a last one at 100%", "[progress]") {
  std::FILE* f = std::tmpfile();
  rdsim::ProgressDisplay display(false, f, false);
  rdsim::EpisodeStats stats;
  for (int i = 1; i <= 100; ++i) display.show(i * 1000, 100000, stats, 1000, i * 1.0);
  display.show(100000, 100000, stats, 1000, 100, true);
  display.finish();
  const std::string text = contents(f);
  std::fclose(f);
  CHECK(text.find('\r') == std::string::npos);
  const auto lines = split(text.substr(0, text.size() - 1), '\n');
  CHECK(lines.size() == 11);  // at 1 s, 11 s, ... 91 s, and the last
  CHECK(lines.back().rfind("100000/100000 steps (100%)", 0) == 0);
}

TEST_CASE("progress: quiet shows nothing", "[progress]") {
  std::FILE* f = std::tmpfile();
  rdsim::ProgressDisplay display(true, f, true);
  display.show(10, 10, {}, 1, 1, true);
  display.finish();
  CHECK(contents(f).empty());
  std::fclose(f);
}

TEST_CASE("progress: a first line that is also the last is shown once", "[progress]") {
  for (const bool tty : {false, true}) {
    std::FILE* f = std::tmpfile();
    rdsim::ProgressDisplay display(false, f, tty);
    display.show(2048, 2048, {}, 1000, 2.0);        // the run's only update
    display.show(2048, 2048, {}, 1000, 2.1, true);  // the end of the run
    display.finish();
    const std::string text = contents(f);
    std::fclose(f);
    INFO(text);
    CHECK(text.find("2048/2048 steps") == text.rfind("2048/2048 steps"));
  }
}
