#include "rdsim/training/progress_display.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rdsim {
namespace {

// Percent done, rounded down: 100 only when t >= total.
int percent(long long t, long long total) {
  if (total <= 0 || t >= total) return 100;
  return static_cast<int>(100 * std::max(t, 0LL) / total);
}

std::string duration(double seconds) {
  const long long s = static_cast<long long>(std::llround(std::max(seconds, 0.0)));
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
  }
  return text;
}

double eta_seconds(long long t, long long total, double sps) {
  return sps > 0 && t < total ? static_cast<double>(total - t) / sps : 0.0;
}

// "success 0.93  return -12.1", or dashes before the first episode ends.
std::string episode_part(const EpisodeStats& s) {
  char text[96];
  if (s.count == 0) return "success -  return -";
  std::snprintf(text, sizeof text, "success %.2f  return %.1f", s.success_rate, s.mean_return);
  return text;
}

}  // namespace

ProgressDisplay::ProgressDisplay(bool quiet, std::FILE* out, std::optional<bool> tty)
    : quiet_(quiet), tty_(tty.value_or(::isatty(::fileno(out)) == 1)), out_(out) {}

int ProgressDisplay::terminal_width() const {
  winsize w{};
  if (::ioctl(::fileno(out_), TIOCGWINSZ, &w) == 0 && w.ws_col > 0) return w.ws_col;
  return 80;
}

std::string ProgressDisplay::terminal_line(long long t, long long total, const EpisodeStats& stats, double sps,
                                           int width) {
  const int pct = percent(t, total);
  const char* success = "-";
  char success_text[32], return_text[48], core[160];
  if (stats.count > 0) {
    std::snprintf(success_text, sizeof success_text, "%.2f", stats.success_rate);
    success = success_text;
  }
  std::snprintf(core, sizeof core, " %3d%%  %lld/%lld steps  success %s  %.0f steps/s  ETA %s", pct, t, total, success,
                sps, duration(eta_seconds(t, total, sps)).c_str());
  std::snprintf(return_text, sizeof return_text, "  return %.1f", stats.mean_return);
  // The last column stays free (writing into it wraps on some terminals, and a wrapped line cannot
  // be rewritten with \r). What does not fit goes: first the mean return, then the bar.
  const int usable = width - 1;
  std::string text = core;
  if (stats.count > 0 && static_cast<int>(text.size() + std::strlen(return_text)) + 12 <= usable) text += return_text;
  const int bar = std::min(usable - static_cast<int>(text.size()) - 2, 30);
  if (bar >= 10) {
    const int filled = bar * pct / 100;
    std::string drawn(static_cast<std::size_t>(bar + 2), '.');
    drawn.front() = '[';
    drawn.back() = ']';
    std::fill_n(drawn.begin() + 1, filled, '#');
    text.insert(0, drawn);
  }
  if (static_cast<int>(text.size()) > usable) text.resize(static_cast<std::size_t>(std::max(usable, 0)));
  return text;
}

std::string ProgressDisplay::plain_line(long long t, long long total, const EpisodeStats& stats, double sps) {
  char text[200];
  std::snprintf(text, sizeof text, "%lld/%lld steps (%d%%)  %s  %.0f steps/s  ETA %s", t, total,
                percent(t, total), episode_part(stats).c_str(), sps, duration(eta_seconds(t, total, sps)).c_str());
  return text;
}

void ProgressDisplay::show(long long t, long long total, const EpisodeStats& stats, double sps, double wall,
                           bool force) {
  if (quiet_) return;
  if (!force && wall - last_ < (tty_ ? 0.1 : 10.0)) return;
  if (force && shown_ && t == last_t_) return;  // the last line is already on screen (a run of one update)
  last_ = wall;
  last_t_ = t;
  if (tty_) {
    std::fprintf(out_, "\r%s\x1b[K", terminal_line(t, total, stats, sps, terminal_width()).c_str());
  } else {
    std::fprintf(out_, "%s\n", plain_line(t, total, stats, sps).c_str());
  }
  std::fflush(out_);
  shown_ = true;
}

void ProgressDisplay::note(const std::string& text) {
  if (quiet_) return;
  std::fprintf(out_, tty_ ? "\r%s\x1b[K\n" : "%s\n", text.c_str());
  std::fflush(out_);
  if (tty_) last_ = -1e9;  // the progress line was overwritten: draw it again at the next show()
}

void ProgressDisplay::finish() {
  if (!quiet_ && tty_ && shown_) {
    std::fputc('\n', out_);
    std::fflush(out_);
  }
}

}  // namespace rdsim
