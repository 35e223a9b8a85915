// libFuzzer target: demonstration-file bytes (*.demo) through the reader `rdsim demos info`,
// `rdsim demos record --append`, `rdsim teleop --record` and training with "demonstrations" use:
// the commit record, the header JSON and spec, each episode record, its JSON and its arrays,
// checksums and counts, then the summary `demos info` prints.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "rdsim/core/error.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/demos/demo_summary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    (void)rdsim::read_commit_record(bytes, bytes.size(), "fuzz.demo");
  } catch (const rdsim::Error&) {
  }
  try {
    const rdsim::DemoFile file = rdsim::decode_demo_file(bytes, "fuzz.demo");
    (void)rdsim::summarize(file);
  } catch (const rdsim::Error&) {
  }
  return 0;
}
