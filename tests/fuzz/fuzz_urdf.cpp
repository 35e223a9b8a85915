// libFuzzer target: URDF text through urdfdom and rdsim's checks (sim/urdf_loader.hpp).
#include <cstddef>
#include <cstdint>
#include <string>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/urdf_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > rdsim::max_urdf_bytes) return 0;  // load_urdf refuses larger files unread
  try {
    (void)rdsim::parse_urdf(std::string(reinterpret_cast<const char*>(data), size), "fuzz.urdf");
  } catch (const rdsim::Error&) {
  }
  return 0;
}
