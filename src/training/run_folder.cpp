#include "rdsim/training/run_folder.hpp"

#include "rdsim/tensorboard/event_writer.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/run_files.hpp"

namespace rdsim {
namespace {

constexpr const char* kLockName = ".rdsim.lock";

// The pid the lock holder wrote; it writes it right after taking the lock, so retry briefly.
std::string holder_pid(int fd) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    if (n > 0) return std::string(buf, static_cast<std::size_t>(n));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return "unknown";
}

}  // namespace

const std::vector<std::string>& RunFolder::run_files() {
  static const std::vector<std::string> files(run_file_names.begin(), run_file_names.end());
  return files;
}

RunFolder::RunFolder(const std::string& dir, Mode mode, const SettingNames& names) : dir_(dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (mode == Mode::Resume && !fs::is_directory(dir_, ec)) throw Error(dir + ": no such run folder to resume");
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) throw Error(dir + ": cannot use as the run folder: " + (ec ? ec.message() : "not a folder"));
  const std::string lock_path = (dir_ / kLockName).string();
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw Error(lock_path + ": cannot create the run folder's lock: " + std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int why = errno;
    const std::string pid = why == EWOULDBLOCK ? holder_pid(lock_fd_) : "";
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (why == EWOULDBLOCK)
      throw Error(dir + ": another rdsim run (pid " + pid + ") is using this folder; wait for it to end or choose another " +
                  names.flag(Setting::LogDir));
    throw Error(lock_path + ": cannot lock the run folder: " + std::strerror(why));
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size()))
    throw Error(lock_path + ": cannot write the run folder's lock: " + std::strerror(errno));

  // Holding the lock, nobody else writes here: temporaries are leftovers of a killed writer.
  for (const auto& entry : fs::directory_iterator(dir_, ec))
    if (is_atomic_write_leftover(entry.path().filename().string())) fs::remove(entry.path(), ec);

  std::vector<std::string> present;
  for (const std::string& f : run_files())
    if (fs::exists(dir_ / f)) present.push_back(f);
  // TensorBoard event files (one per process that trained here) belong to the run as well.
  for (const auto& entry : fs::directory_iterator(dir_, ec))
    if (is_event_file_name(entry.path().filename().string())) present.push_back(entry.path().filename().string());
  if (mode == Mode::New && !present.empty()) {
    std::string list;
    for (const auto& f : present) list += (list.empty() ? "" : ", ") + f;
    // --resume needs a checkpoint: a run that ended before its first one (its checkpoint could
    // not be written) can only start again.
    if (!fs::exists(dir_ / checkpoint_file_name))
      throw Error(dir + ": holds the files of a run that ended before its first checkpoint (" + list +
                  "), so it cannot be resumed; start again with " + names.flag(Setting::Overwrite) +
                  " (deletes them), or choose another " + names.flag(Setting::LogDir));
    throw Error(dir + ": holds the files of another run (" + list + "); continue it with " + names.with(Setting::Resume, dir) +
                ", start again with " + names.flag(Setting::Overwrite) + " (deletes them), or choose another " +
                names.flag(Setting::LogDir));
  }
  if (mode == Mode::Overwrite) {
    for (const auto& f : present) {
      fs::remove(dir_ / f, ec);
      if (ec) throw Error(file(f) + ": cannot remove: " + ec.message());
    }
  }
}

RunFolder::~RunFolder() {
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock
}

}  // namespace rdsim
