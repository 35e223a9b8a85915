#pragma once
// Assimp's file access through rdsim's one rule for reading files (rdsim/core/input_file.hpp): the
// mesh file and any file it names (an OBJ's .mtl) are opened without blocking, must be regular
// files, and are read whole into memory, all of them together at most `budget` bytes. Assimp then
// parses from memory; nothing it does can block on a FIFO or read a device.
#include <assimp/IOSystem.hpp>

#include <cstdint>
#include <string>

namespace rdsim {

class AssimpInput : public Assimp::IOSystem {
public:
  // `main` is the mesh file's path and `bytes` its contents (already read by the caller).
  AssimpInput(std::string main, std::string bytes, std::uint64_t budget);

  bool Exists(const char* file) const override;
  char getOsSeparator() const override { return '/'; }
  // The main file from memory; another file read now, or null (Assimp then goes on without it:
  // a missing .mtl only loses colours) when it cannot be read under the rule or the budget.
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;
  void Close(Assimp::IOStream* stream) override;

private:
  std::string main_, bytes_;
  std::uint64_t budget_;  // bytes still allowed for the files the mesh names
};

}  // namespace rdsim
