// libFuzzer target: model.bin bytes through what a controller links (rdsim_policy): the envelope and
// the policy part (every operation's sizes and values), then one action for an all-zero observation.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "rdsim/core/error.hpp"
#include "rdsim/policy/policy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const rdsim::Policy policy = rdsim::Policy::from_bytes(bytes, "fuzz.bin");
    rdsim::Observation zero;
    if (policy.observation_space().type == rdsim::ObsType::UInt8)
      zero.pixels.assign(static_cast<std::size_t>(policy.observation_space().size()), 0);
    else
      zero.values = Eigen::VectorXf::Zero(policy.observation_space().size());
    (void)policy.act(zero);
  } catch (const rdsim::Error&) {
  }
  return 0;
}
