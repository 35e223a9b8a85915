#include "rdsim/core/input_file.hpp"

#include <cerrno>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <linux/openat2.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

// O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer. O_NOCTTY: a terminal
// device never becomes our controlling terminal. Regular files ignore both.
constexpr int kOpenFlags = O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC;

FileOpenError open_error(const std::string& path, int why) {
  if (why == ELOOP || why == EXDEV)
    return FileOpenError(path + ": cannot open: a symbolic link leads out of the folder it is read from", why);
  if (why == ENXIO) return FileOpenError(path + ": is not a regular file (it is a socket, or a device with nothing behind it)", why);
  return FileOpenError(path + ": cannot open: " + std::strerror(why), why);
}

// openat2(2) RESOLVE_BENEATH; -1 with errno ENOSYS on kernels before 5.6.
int openat_beneath(int dir_fd, const std::string& relative) {
#ifdef SYS_openat2
  open_how how{};
  how.flags = static_cast<std::uint64_t>(kOpenFlags);
  how.resolve = RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS;
  int fd;
  do fd = static_cast<int>(::syscall(SYS_openat2, dir_fd, relative.c_str(), &how, sizeof how));
  while (fd < 0 && errno == EINTR);  // RESOLVE_BENEATH may also ask for a retry (EAGAIN): rare
  if (fd < 0 && errno == EAGAIN) fd = static_cast<int>(::syscall(SYS_openat2, dir_fd, relative.c_str(), &how, sizeof how));
  return fd;
#else
  (void)dir_fd;
  (void)relative;
  errno = ENOSYS;
  return -1;
#endif
}

// The fallback: one component at a time, never following a link.
int openat_nofollow(int dir_fd, const std::string& relative) {
  int at = dir_fd;
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = relative.find('/', start);
    const std::string part = relative.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    const bool last = slash == std::string::npos;
    const int fd = part.empty() || part == "."
                       ? ::dup(at)
                       : ::openat(at, part.c_str(), (last ? kOpenFlags : O_RDONLY | O_DIRECTORY | O_CLOEXEC) | O_NOFOLLOW);
    const int why = errno;
    if (at != dir_fd) ::close(at);
    if (fd < 0) {
      errno = why;
      return -1;
    }
    if (last) return fd;
    at = fd;
    start = slash + 1;
  }
}

}  // namespace

bool FileOpenError::link_out() const { return code_ == ELOOP || code_ == EXDEV; }

std::string describe_file_type(unsigned mode) {
  switch (mode & S_IFMT) {
    case S_IFREG: return "a regular file";
    case S_IFDIR: return "a folder";
    case S_IFIFO: return "a FIFO";
    case S_IFCHR: return "a character device";
    case S_IFBLK: return "a block device";
    case S_IFSOCK: return "a socket";
    case S_IFLNK: return "a symbolic link";
    default: return "not a regular file";
  }
}

InputFile::InputFile(int fd, std::string path, std::uint64_t max_bytes) : fd_(fd), path_(std::move(path)), max_bytes_(max_bytes) {
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int why = errno;
    ::close(fd_);
    throw Error(path_ + ": cannot read: " + std::strerror(why));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd_);
    throw Error(path_ + ": is not a regular file (it is " + describe_file_type(st.st_mode) + ")");
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
  if (size_ > max_bytes_) {
    ::close(fd_);
    throw Error(path_ + ": is " + std::to_string(size_) + " bytes, more than the " + std::to_string(max_bytes_) +
                " bytes rdsim reads from such a file");
  }
  // Reads of a regular file never block anyway; clear the flag for whoever takes the descriptor.
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_NONBLOCK);
}

InputFile::InputFile(const std::string& path, std::uint64_t max_bytes)
    : InputFile([&] {
        const int fd = ::open(path.c_str(), kOpenFlags);
        if (fd < 0) throw open_error(path, errno);
        return fd;
      }(),
                path, max_bytes) {}

InputFile InputFile::beneath(const std::string& root, const std::string& relative, std::uint64_t max_bytes) {
  const std::string shown = root + "/" + relative;
  if (relative.empty() || relative[0] == '/' || relative == ".." || relative.rfind("../", 0) == 0 ||
      relative.find("/../") != std::string::npos || (relative.size() >= 3 && relative.compare(relative.size() - 3, 3, "/..") == 0))
    throw FileOpenError(shown + ": cannot open: the path leaves its folder", EXDEV);
  const int dir_fd = ::open(root.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd < 0) throw open_error(root, errno);
  int fd = openat_beneath(dir_fd, relative);
  if (fd < 0 && (errno == ENOSYS || errno == EPERM)) fd = openat_nofollow(dir_fd, relative);  // EPERM: a seccomp filter
  const int why = errno;
  ::close(dir_fd);
  if (fd < 0) throw open_error(shown, why);
  return InputFile(fd, shown, max_bytes);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

InputFile::InputFile(InputFile&& other) noexcept
    : fd_(other.fd_), path_(std::move(other.path_)), size_(other.size_), max_bytes_(other.max_bytes_), read_(other.read_) {
  other.fd_ = -1;
}

int InputFile::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

std::string InputFile::read(std::uint64_t n) {
  std::string out;
  out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n, size_ > read_ ? size_ - read_ : 0)));
  std::vector<char> chunk(static_cast<std::size_t>(std::min<std::uint64_t>(n, 1 << 16)) + 1);
  while (out.size() < n) {
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(n - out.size(), chunk.size()));
    const ssize_t got = ::read(fd_, chunk.data(), want);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw Error(path_ + ": cannot read: " + std::strerror(errno));
    if (got == 0) break;
    out.append(chunk.data(), static_cast<std::size_t>(got));
  }
  read_ += out.size();
  return out;
}

std::string InputFile::read_rest() {
  const std::uint64_t allowed = max_bytes_ - std::min(read_, max_bytes_);
  std::string out = read(allowed == UINT64_MAX ? allowed : allowed + 1);
  if (out.size() > allowed)
    throw Error(path_ + ": holds more than the " + std::to_string(max_bytes_) + " bytes rdsim reads from such a file");
  return out;
}

}  // namespace rdsim
