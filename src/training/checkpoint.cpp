#include "rdsim/training/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/csv_reader.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

std::string checkpoint_payload(const Algorithm& algo, const VecEnv& vec, const TrainerState& state) {
  std::ostringstream out(std::ios::binary);
  algo.save(out, true);
  write_u64(out, static_cast<std::uint64_t>(state.progress_rows));
  write_u64(out, static_cast<std::uint64_t>(state.episode_rows));
  write_u64(out, static_cast<std::uint64_t>(state.updates));
  if (state.eval) {
    write_u64(out, static_cast<std::uint64_t>(state.eval->rows));
    write_f64(out, state.eval->best_mean_return);
  }
  vec.save(out);
  return std::move(out).str();
}

TrainerState restore_checkpoint(const std::string& payload, Algorithm& algo, VecEnv& vec, const std::string& source,
                                bool report, bool eval) {
  std::istringstream in(payload, std::ios::binary);
  algo.load(in, true, source);
  const std::uint64_t progress_rows = read_u64(in, source);
  const std::uint64_t episode_rows = read_u64(in, source);
  const std::uint64_t updates = read_u64(in, source);
  constexpr std::uint64_t far = 1ull << 50;  // beyond any run: a negative count read as unsigned
  if (progress_rows > far || episode_rows > far || updates > far)
    throw Error(source + ": checkpoint counters are out of range (damaged file?)");
  TrainerState s;
  s.progress_rows = static_cast<long long>(progress_rows);
  s.episode_rows = static_cast<long long>(episode_rows);
  s.updates = static_cast<long long>(updates);
  if (eval) {
    const std::uint64_t rows = read_u64(in, source);
    const double best = read_f64(in, source);
    // -inf before the first evaluation; never NaN or +inf
    if (rows > far || std::isnan(best) || best == std::numeric_limits<double>::infinity())
      throw Error(source + ": checkpoint holds evaluation state out of range (damaged file?)");
    s.eval = EvalState{static_cast<long long>(rows), best};
  }
  if (!vec.load(in, source) && report) {
    std::fprintf(stderr, "rdsim: note: these envs cannot save their state; the resumed run starts fresh "
                         "episodes and will not match an uninterrupted run exactly\n");
  }
  if (in.peek() != std::char_traits<char>::eof()) throw Error(source + ": file is damaged (unexpected trailing data)");
  return s;
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

CheckpointSchedule::CheckpointSchedule(long long interval_steps, double interval_seconds, long long steps)
    : interval_(interval_steps), seconds_(interval_seconds), last_(Clock::now()) {
  next_step_ = interval_ > 0 ? (steps / interval_ + 1) * interval_ : 0;
}

bool CheckpointSchedule::due(long long steps) const {
  if (interval_ > 0 && steps >= next_step_) return true;
  return seconds_ > 0.0 && seconds_since(last_) >= std::max(seconds_, 20.0 * last_duration_);
}

void CheckpointSchedule::done(long long steps) {
  last_ = Clock::now();
  last_duration_ = seconds_since(started_);
  if (interval_ > 0) next_step_ = (steps / interval_ + 1) * interval_;
}

void check_log_rows(const std::string& path, long long rows, const std::string& checkpoint) {
  if (rows == 0) return;
  std::error_code ec;
  const long long found = std::filesystem::exists(path, ec) ? count_csv_rows(path, rows) : 0;  // a regular file only
  if (found < rows)
    throw Error(checkpoint + ": records " + std::to_string(rows) + " rows of " + path + ", which has " +
                std::to_string(found) + " (logs of another run, or cut short?)");
}

}  // namespace rdsim
