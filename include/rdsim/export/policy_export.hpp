#pragma once
#include <string>

// `rdsim export MODEL --onnx FILE` and Python's Model.export_onnx: a saved policy as an ONNX model
// (onnx_export.hpp), checked against rdsim's own actions before it is written.
namespace rdsim {

struct ExportSummary {
  std::string algorithm, env;  // "ppo", "jaka_button"
  std::string spec;            // describe_spec() of the model's env
  long long bytes = 0;         // of the written file
  int checked = 0;             // observations on which the graph's program was held against act()
  double max_difference = 0.0;  // the largest |program - act()| over them (0 for discrete policies that agree)
};

// Loads `model_path` (training/saved_policy.hpp), builds its policy program, compares the program's
// actions with the algorithm's deterministic act() on 256 seeded random observations (rdsim::Error
// if any differs by more than 1e-5, or a discrete action differs), and writes the ONNX model to
// `out_path` atomically. rdsim::Error naming the file for a damaged model or the random agent's
// (which has no policy).
ExportSummary export_onnx(const std::string& model_path, const std::string& out_path);

}  // namespace rdsim
