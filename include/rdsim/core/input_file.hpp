#pragma once
#include <cstdint>
#include <string>

#include "rdsim/core/error.hpp"

// The one rule for every file rdsim reads (configs, models, checkpoints, demonstrations, URDFs,
// key files, run logs): it must be a regular file, and no larger than the limit for its kind.
// The file is opened without blocking (O_NONBLOCK, so a FIFO with no writer cannot hold the open)
// and checked with fstat on that descriptor, so a FIFO, device, socket or folder is refused at
// once, before a byte is read ("is not a regular file (it is a FIFO)"), and nothing can swap the
// file between the check and the read.
// Readers then check a format's header before reading its body (demo_file.cpp, model_file.cpp).
namespace rdsim {

// What InputFile throws when the open itself fails; code() is the errno (ENOENT: no such file;
// ELOOP or EXDEV: a symbolic link leads out of the folder it is opened below).
class FileOpenError : public Error {
public:
  FileOpenError(const std::string& message, int code) : Error(message), code_(code) {}
  int code() const { return code_; }
  bool link_out() const;

private:
  int code_;
};

class InputFile {
public:
  // Opens `path`. rdsim::Error naming it when it cannot be opened, is not a regular file, or is
  // larger than `max_bytes`.
  InputFile(const std::string& path, std::uint64_t max_bytes);
  // Opens `relative` (a path below `root`, no "..") without leaving `root`: a symbolic link that
  // points out of it, anywhere on the way, is refused in the same system call that opens the file
  // (openat2 RESOLVE_BENEATH; on kernels before 5.6, openat with O_NOFOLLOW on every component,
  // which refuses every link). rdsim::Error as above; the message names `root`/`relative`.
  static InputFile beneath(const std::string& root, const std::string& relative, std::uint64_t max_bytes);

  ~InputFile();
  InputFile(InputFile&& other) noexcept;
  InputFile& operator=(InputFile&&) = delete;
  InputFile(const InputFile&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size() const { return size_; }  // bytes when it was opened
  int fd() const { return fd_; }
  // Hands the descriptor over (the caller closes it).
  int release();

  // Up to `n` bytes from the current position (fewer only at the end of the file).
  std::string read(std::uint64_t n);
  // Everything from the current position to the end; rdsim::Error when the file has grown past
  // the limit since it was opened.
  std::string read_rest();

private:
  InputFile(int fd, std::string path, std::uint64_t max_bytes);

  int fd_ = -1;
  std::string path_;
  std::uint64_t size_ = 0, max_bytes_ = 0, read_ = 0;
};

// Whether a regular file, a folder, a FIFO... ("a FIFO", "a character device"): for messages.
std::string describe_file_type(unsigned mode);

}  // namespace rdsim
