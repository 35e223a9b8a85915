#pragma once
#include <string>
#include <string_view>

#include "rdsim/policy/policy_program.hpp"

// A PolicyProgram as bytes: the policy part of a model file (core/model_envelope.hpp). Layout
// (little-endian, core/binary_io.hpp; matrices as nn/serialize.hpp writes them):
//   "RDPP" | u32 version (1) | string algorithm | u32 input size | u32 pixels (0/1)
//   | pixels: u32 height, width, channels | u32 discrete (0/1) | u32 action size | u32 op count
//   | per op: u32 kind (PolicyOp::Kind), then by kind:
//       Standardize: f32 clip, mean (n x 1), 1 / std (n x 1)      Scale: f32 factor
//       Dense: u32 outputs m, weight (m x n), bias (m x 1)        Activate: u32 (0 tanh, 1 relu, 2 identity)
//       KeepRows: u32 rows                                         Clip, Rescale: low, high (n x 1)
//       ArgMax: nothing
//       Conv: u32 input height, width, channels, out channels, kernel, stride, padding,
//             weight (out channels x kernel * kernel * in channels), bias (out channels x 1)
// where n is the number of values each observation has at that op. Decoding checks every size
// against n before it allocates, every value is finite, and the last op leaves one value (discrete)
// or `action size` values, so a damaged or edited policy is a clear error, never a crash.
namespace rdsim {

std::string encode_policy_program(const PolicyProgram& program);
// rdsim::Error naming `source` for anything out of place.
PolicyProgram decode_policy_program(std::string_view bytes, const std::string& source);

}  // namespace rdsim
