// libFuzzer target: mesh files through Assimp and rdsim's checks (sim/mesh_file.hpp), then the
// convex hull a collision mesh gets. The first byte picks the format (its value mod 3: STL, OBJ,
// DAE; the seeds use '0', '1', '2'); the rest is the file, written where Assimp reads it by name.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/mesh_file.hpp"
#include "../scratch_dir.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 || size - 1 > rdsim::max_mesh_bytes) return 0;  // larger files are refused unread
  static const char* const kExtensions[] = {".stl", ".obj", ".dae"};
  static const rdsim::test::ScratchDir dir("fuzz_mesh");  // removed when the fuzzer exits
  const std::string file = dir / (std::string("input") + kExtensions[data[0] % 3]);
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  try {
    const rdsim::TriangleMesh mesh = rdsim::read_mesh_file(file, Eigen::Vector3d(0.5, -1.0, 2.0));
    (void)rdsim::convex_hull(mesh);
  } catch (const rdsim::Error&) {
  }
  std::filesystem::remove(file);
  return 0;
}
