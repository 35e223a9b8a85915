#include "rdsim/tensorboard/event_writer.hpp"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <unistd.h>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/tensorboard/tfrecord.hpp"

namespace rdsim {
namespace {

// The host name as a file name part: letters, digits, '-', '_' and '.'; anything else becomes '_'.
std::string host_name() {
  char name[256] = "";
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "localhost";
  std::string out = name;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return out;
}

constexpr const char* kEventFilePrefix = "events.out.tfevents.";

// events.out.tfevents.<seconds, 10 digits>.<host>.<pid>.<n>: name order is creation order
// across seconds; pid and a per-process count keep two writers in one second apart.
std::string event_file_name(double wall_time) {
  static std::atomic<int> count{0};
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%010lld", static_cast<long long>(wall_time));
  return std::string(kEventFilePrefix) + seconds + "." + host_name() + "." + std::to_string(::getpid()) + "." +
         std::to_string(count++);
}

}  // namespace

double EventWriter::now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

EventWriter::EventWriter(const std::string& dir, double wall_time)
    : path_((std::filesystem::path(dir) / event_file_name(wall_time)).string()) {
  create_parent_folders(path_);
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error(path_ + ": cannot create: " + std::strerror(errno));
  add(encode_file_version_event(wall_time));
  flush();
}

EventWriter::~EventWriter() {
  try {
    flush();
  } catch (const Error&) {
    // A destructor cannot report it; flush() callers see the error.
  }
  if (fd_ >= 0) ::close(fd_);
}

void EventWriter::add(const std::string& event) { pending_ += tfrecord(event); }

void EventWriter::scalar(const std::string& tag, long long step, double value, double wall_time) {
  add(encode_scalars_event(wall_time, step, {{tag, value}}));
}

void EventWriter::scalars(long long step, const std::vector<Scalar>& values, double wall_time) {
  if (!values.empty()) add(encode_scalars_event(wall_time, step, values));
}

void EventWriter::session_start(long long step, double wall_time) { add(encode_session_start_event(wall_time, step)); }

void EventWriter::flush() {
  std::size_t done = 0;
  while (done < pending_.size()) {
    const ssize_t n = ::write(fd_, pending_.data() + done, pending_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      pending_.erase(0, done);
      throw Error(path_ + ": cannot write: " + std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
  pending_.clear();
}

bool is_event_file_name(const std::string& name) { return name.rfind(kEventFilePrefix, 0) == 0; }

std::vector<Scalar> scalars_of_row(const std::vector<std::string>& columns, const std::vector<std::string>& cells) {
  std::vector<Scalar> out;
  for (std::size_t i = 0; i < columns.size() && i < cells.size(); ++i) {
    const char* text = cells[i].c_str();
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0' || std::isnan(value)) continue;
    out.emplace_back(columns[i], value);
  }
  return out;
}

}  // namespace rdsim
