// libFuzzer target: a training config from bytes, through the same path as `rdsim train --config`
// (bounded JSON text, then every key's rules). Anything but rdsim::Error escaping is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "rdsim/training/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/json_text.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    nlohmann::json json = rdsim::parse_json(text, "fuzz.json");
    rdsim::apply_overrides(json, {{"--timesteps", "total_timesteps", "1000"}}, "fuzz.json");
    const rdsim::TrainConfig config = rdsim::parse_train_config(json, "fuzz.json", "fuzz");
    // The resolved config must read back to itself.
    (void)rdsim::parse_train_config(rdsim::to_json(config), "fuzz.json (resolved)", "fuzz");
  } catch (const rdsim::Error&) {
  }
  return 0;
}
