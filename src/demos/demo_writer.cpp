#include "rdsim/demos/demo_writer.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <unistd.h>

#include "demo_layout.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_fit.hpp"

namespace rdsim {

DemoWriter::DemoWriter(const std::string& path, const nlohmann::json& env_config, const Spec& spec, bool append)
    : path_(path), spec_(spec) {
  const bool exists = std::filesystem::exists(path);
  if (exists && !append) throw Error(path + ": already exists (append to it, or choose another file)");
  if (exists) {
    const DemoFile file = read_demo_file(path);
    const std::string problem = demos_fit_problem(file.env_config, file.spec, env_config, spec);
    if (!problem.empty()) throw Error(path + ": cannot append: " + problem);
    committed_ = std::filesystem::file_size(path) - file.interrupted_bytes;
    episodes_ = static_cast<long long>(file.episodes.size());
  } else {
    const std::string fresh = encode_demo_file(env_config, spec);
    write_file_atomic(path, fresh);
    committed_ = fresh.size();
  }
  fd_ = ::open(path.c_str(), O_RDWR);
  if (fd_ < 0) throw Error(path + ": cannot open for writing: " + std::strerror(errno));
  // Bytes of an episode whose write a crash interrupted: never committed, so drop them.
  if (::ftruncate(fd_, static_cast<off_t>(committed_)) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd_);
    throw Error(path + ": cannot write: " + why);
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
