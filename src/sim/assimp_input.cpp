#include "assimp_input.hpp"

#include <assimp/MemoryIOWrapper.h>
#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <memory>

#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"

namespace rdsim {
namespace {

// A stream over a copy of `bytes` that it owns (Assimp's MemoryIOStream frees with delete[]).
Assimp::IOStream* stream_of(const std::string& bytes) {
  auto* copy = new std::uint8_t[bytes.size() + 1];
  std::memcpy(copy, bytes.data(), bytes.size());
  return new Assimp::MemoryIOStream(copy, bytes.size(), true);
}

bool same_file(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

}  // namespace

AssimpInput::AssimpInput(std::string main, std::string bytes, std::uint64_t budget)
    : main_(std::move(main)), bytes_(std::move(bytes)), budget_(budget) {}

bool AssimpInput::Exists(const char* file) const {
  struct stat st;
  return file && (main_ == file || (::stat(file, &st) == 0 && S_ISREG(st.st_mode)));
}

Assimp::IOStream* AssimpInput::Open(const char* file, const char* mode) {
  if (!file || !mode || std::strchr(mode, 'w') || std::strchr(mode, 'a')) return nullptr;  // never writes
  if (same_file(main_, file)) return stream_of(bytes_);
  try {
    InputFile in(file, budget_);
    std::string bytes = in.read_rest();
    budget_ -= bytes.size();
    return stream_of(bytes);
  } catch (const Error&) {
    return nullptr;
  }
}

void AssimpInput::Close(Assimp::IOStream* stream) { delete stream; }

}  // namespace rdsim
