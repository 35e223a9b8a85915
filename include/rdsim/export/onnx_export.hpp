#pragma once
#include <map>
#include <string>

#include "rdsim/policy/policy_program.hpp"

// A policy program (algorithms/policy_program.hpp) as an ONNX model, built with ONNX's own protobuf
// classes (Debian's libonnx-dev) and checked with its checker: input "observation" (float32
// [batch, observation size], or for pixel policies uint8 [batch, height, width, channels]), output "action"
// (int64 [batch] for a discrete policy, float32 [batch, action size] for a Box one), opset 13. The
// graph computes what run_policy_program() computes: the trained policy's deterministic action.
namespace rdsim {

// The serialised model. `metadata`: key-value pairs for the model's metadata_props (the env, the
// algorithm, the source file). rdsim::Error when ONNX's checker refuses the graph.
std::string onnx_model_bytes(const PolicyProgram& program, const std::map<std::string, std::string>& metadata);

}  // namespace rdsim
