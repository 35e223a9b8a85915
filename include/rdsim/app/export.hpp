#pragma once
#include <string>

// `rdsim export MODEL --onnx FILE`: a trained policy as an ONNX model for a robot's controller
// (src/app/export.cpp; the work is export/policy_export.hpp).
namespace rdsim {

struct ExportOptions {
  std::string model_path;  // model.bin or checkpoint.bin
  std::string onnx_path;   // where to write the ONNX model
};
int export_command(const ExportOptions& options);

}  // namespace rdsim
