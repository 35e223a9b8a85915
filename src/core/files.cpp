#include "rdsim/core/files.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"

namespace rdsim {
namespace {

constexpr std::string_view kTmpSuffix = ".tmp";

// Closes the descriptor and removes the temporary file unless released.
struct TempFile {
  int fd = -1;
  std::string path;
  ~TempFile() {
    if (fd >= 0) ::close(fd);
    if (!path.empty()) ::unlink(path.c_str());
  }
};

bool write_all(int fd, std::string_view data) {
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

bool is_atomic_write_leftover(const std::string& name) {
  // ".NAME.XXXXXX.tmp": a dot, a name, a dot, six characters, ".tmp".
  if (name.size() < 1 + 1 + 1 + 6 + kTmpSuffix.size() || name[0] != '.') return false;
  if (name.compare(name.size() - kTmpSuffix.size(), kTmpSuffix.size(), kTmpSuffix) != 0) return false;
  return name[name.size() - kTmpSuffix.size() - 7] == '.';
}

void create_parent_folders(const std::string& path) {
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  // create_directories reports no error for an existing non-folder on some libstdc++ versions.
  if (!ec && !std::filesystem::is_directory(dir, ec)) ec = std::make_error_code(std::errc::not_a_directory);
  if (ec) throw Error(path + ": cannot create its folder " + dir.string() + ": " + ec.message());
}

void write_file_atomic(const std::string& path, std::string_view data) {
  create_parent_folders(path);
  const std::filesystem::path target(path);
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::string name = ".";
  name += target.filename().string();
  name += ".XXXXXX";
  name += kTmpSuffix;
  std::string pattern = (dir / name).string();
  TempFile tmp;
  tmp.fd = ::mkstemps(pattern.data(), static_cast<int>(kTmpSuffix.size()));
  if (tmp.fd < 0) throw Error(path + ": cannot write: " + std::strerror(errno));
  tmp.path = pattern;
  // mkstemp makes the file private (0600); results are ordinary files.
  if (::fchmod(tmp.fd, 0644) != 0 || !write_all(tmp.fd, data)) throw Error(path + ": cannot write: " + std::strerror(errno));
  // fsync before the rename, so a crash after it can never leave an empty file behind the name.
  if (::fsync(tmp.fd) != 0) throw Error(path + ": cannot write: " + std::strerror(errno));
  const int fd = tmp.fd;
  tmp.fd = -1;
  if (::close(fd) != 0) throw Error(path + ": cannot write: " + std::strerror(errno));
  if (std::rename(tmp.path.c_str(), path.c_str()) != 0) throw Error(path + ": cannot replace: " + std::strerror(errno));
  tmp.path.clear();
  // The rename itself reaches the disk with the folder's fsync.
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

std::string read_file(const std::string& path, std::uint64_t max_bytes) { return InputFile(path, max_bytes).read_rest(); }

void require_file_or_hint(const std::string& path, const std::string& how_to_make_it) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) && !ec)
    throw Error(path + ": cannot open: " + std::strerror(ENOENT) + "; make it with: " + how_to_make_it);
}

std::string read_file_or_hint(const std::string& path, const std::string& how_to_make_it, std::uint64_t max_bytes) {
  require_file_or_hint(path, how_to_make_it);
  return read_file(path, max_bytes);
}

}  // namespace rdsim
