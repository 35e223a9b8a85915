// libFuzzer target: the server's request parser (remote/request.hpp), the first code that reads
// a network message. Input bytes are split into frames at each "\xff\xfe" pair (so the fuzzer
// explores part counts too). Built like the other targets (tests/fuzz/CMakeLists.txt): a corpus
// replay in every ctest run, a libFuzzer binary with RDSIM_FUZZ (tools/fuzz.sh).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "rdsim/remote/request.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string_view> frames;
  std::size_t start = 0;
  for (std::size_t at = input.find("\xff\xfe"); at != std::string_view::npos; at = input.find("\xff\xfe", start)) {
    frames.push_back(input.substr(start, at - start));
    start = at + 2;
  }
  frames.push_back(input.substr(start));
  const rdsim::remote::ParsedRequest parsed = rdsim::remote::parse_request(frames);
  // Exactly one of: a request, or an error message.
  if (parsed.request.has_value() == !parsed.error.empty()) __builtin_trap();
  return 0;
}
