#include "rdsim/core/env_config.hpp"

#include "rdsim/core/error.hpp"

namespace rdsim {

const char* to_string(ObservationMode mode) {
  return mode == ObservationMode::RawPixels ? "raw_pixels" : "ground_truth";
}

const char* to_string(RenderMode mode) { return mode == RenderMode::RgbArray ? "rgb_array" : "none"; }

void EnvConfig::throw_missing_group() const {
  throw Error("env " + name + ": its config has no options of that kind (start from default_env_config(\"" + name +
              "\"); envs/registry.hpp)");
}

}  // namespace rdsim
