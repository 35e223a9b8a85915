#include "rdsim/demos/demo_writer.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "demo_layout.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/input_file.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_fit.hpp"

namespace rdsim {

namespace {

// O_NONBLOCK: a FIFO at the path must not hold the open (it is refused right after, by fstat).
constexpr int kOpenFlags = O_RDWR | O_NONBLOCK | O_NOCTTY | O_CLOEXEC;

// The exclusive lock every writer of a file holds while it lives (flock: the kernel drops it when
// the process ends, however it ends). False when another process holds it.
bool lock_now(int fd, const std::string& path) {
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return true;
  if (errno == EWOULDBLOCK) return false;
  throw Error(path + ": cannot lock the demonstration file: " + std::strerror(errno));
}

[[noreturn]] void refuse_second_writer(const std::string& path) {
  throw Error(path + ": another rdsim process is recording to this demonstration file; wait for it to end or "
                     "choose another file");
}

// Writes `bytes` to a new temporary file beside `path`, locked, then links it to `path`: the file
// appears whole and already locked, and never replaces one another writer created meanwhile.
// The descriptor, or -1 when `path` exists by now.
int create_locked(const std::string& path, const std::string& bytes) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string name = ".";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "." + std::string
  name += target.filename().string();
  name += ".XXXXXX.tmp";
  std::string tmp = (dir / name).string();
  create_parent_folders(path);  // like every other output file: its folder is made
  const int fd = ::mkstemps(tmp.data(), 4);
  if (fd < 0) throw Error(path + ": cannot create: " + std::strerror(errno));
  const auto fail = [&](const char* what) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    ::unlink(tmp.c_str());
    throw Error(path + ": " + what + ": " + why);
  };
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot write");
    done += static_cast<std::size_t>(n);
  }
  if (::fchmod(fd, 0644) != 0 || ::fsync(fd) != 0) fail("cannot write");
  if (!lock_now(fd, path)) fail("cannot lock");
  if (::link(tmp.c_str(), path.c_str()) != 0) {
    if (errno != EEXIST) fail("cannot create");
    ::close(fd);
    ::unlink(tmp.c_str());
    return -1;
  }
  ::unlink(tmp.c_str());
  // The new name reaches the disk with the folder's fsync.
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
  return fd;
}

}  // namespace

DemoWriter::DemoWriter(const std::string& path, const nlohmann::json& env_config, const Spec& spec, bool append)
    : path_(path), spec_(spec) {
  for (int attempt = 0; fd_ < 0; ++attempt) {
    fd_ = ::open(path.c_str(), kOpenFlags);
    if (fd_ >= 0) break;
    if (errno != ENOENT || attempt > 0) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
    const std::string fresh = encode_demo_file(env_config, spec);
    fd_ = create_locked(path, fresh);  // -1: another writer created it first
    if (fd_ >= 0) {
      committed_ = fresh.size();
      return;
    }
  }
  try {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) throw Error(path + ": cannot read: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Error(path + ": is not a regular file (it is " + describe_file_type(st.st_mode) + ")");
    if (!append) throw Error(path + ": already exists (append to it, or choose another file)");
    if (!lock_now(fd_, path)) refuse_second_writer(path);
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
    // Holding the lock, nobody else writes it: what it holds now is what we continue.
    const DemoFile file = read_demo_file(path);
    const std::string problem = demos_fit_problem(file.env_config, file.spec, env_config, spec);
    if (!problem.empty()) throw Error(path + ": cannot append: " + problem);
    committed_ = static_cast<std::uint64_t>(st.st_size) - file.interrupted_bytes;
    episodes_ = static_cast<long long>(file.episodes.size());
    // Bytes of an episode whose write a crash interrupted: never committed, so drop them.
    if (::ftruncate(fd_, static_cast<off_t>(committed_)) != 0) throw Error(path + ": cannot write: " + std::strerror(errno));
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

DemoWriter::~DemoWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void DemoWriter::write_at(const std::string& bytes, unsigned long long offset) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(path_ + ": cannot write: " + std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
}

void DemoWriter::sync() {
  if (::fsync(fd_) != 0) throw Error(path_ + ": cannot write: " + std::strerror(errno));
}

void DemoWriter::append(const DemoEpisode& episode) {
  const std::string record =
      encode_demo_episode(episode, spec_, path_ + ": episode " + std::to_string(episodes_ + 1));
  bool commit_started = false;
  try {
    // The record first, on disk; only then the commit record that makes readers see it.
    write_at(record, committed_);
    sync();
    commit_started = true;
    write_at(demo_layout::commit_record(committed_ + record.size(), static_cast<std::uint64_t>(episodes_ + 1)),
             demo_layout::commit_offset);
    sync();
  } catch (const Error&) {
    // Bytes beyond the committed ones are not part of the file; drop them if we can (readers
    // ignore them anyway). Once the commit record may have changed, the record must stay.
    if (!commit_started && ::ftruncate(fd_, static_cast<off_t>(committed_)) != 0) {
    }
    throw;
  }
  committed_ += record.size();
  ++episodes_;
}

}  // namespace rdsim
