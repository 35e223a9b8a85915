#pragma once
#include <cstdio>
#include <optional>
#include <string>

#include "rdsim/vecenv/episode_tracker.hpp"

// The progress `rdsim train` shows on stderr. On a terminal: one line rewritten in place, at most
// ten times a second, with a bar, the percentage, steps, success rate, mean return, steps/s and the
// time left, fitted to the terminal's width. Otherwise (a log file, a pipe): a plain line every
// 10 s. The last line (force) is shown unless the same steps' line already is, and reads 100% once
// the run reached its total (the trainer passes the steps the run ends on: total_timesteps rounded up
// to whole updates); the percentage is rounded down, so 100% means done.
namespace rdsim {

class ProgressDisplay {
public:
  // tty: whether `out` is a terminal (default: asks isatty).
  explicit ProgressDisplay(bool quiet, std::FILE* out = stderr, std::optional<bool> tty = std::nullopt);

  // t of total steps done; stats over the last episodes; sps: steps/s so far; wall: seconds so far.
  void show(long long t, long long total, const EpisodeStats& stats, double sps, double wall, bool force = false);
  // Ends the terminal line after the last show().
  void finish();
  // A line of its own (an evaluation's result) above the progress line, which the next show() redraws.
  void note(const std::string& text);

  // The text of one terminal line at most `width` characters wide (exposed for tests).
  static std::string terminal_line(long long t, long long total, const EpisodeStats& stats, double sps, int width);
  static std::string plain_line(long long t, long long total, const EpisodeStats& stats, double sps);

private:
  int terminal_width() const;

  bool quiet_, tty_;
  std::FILE* out_;
  bool shown_ = false;
  double last_ = -1e9;
  long long last_t_ = -1;  // the steps of the line last shown
};

}  // namespace rdsim
