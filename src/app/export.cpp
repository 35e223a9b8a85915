// `rdsim export`: a saved policy as an ONNX model.
#include "rdsim/app/export.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "rdsim/app/command.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/export/policy_export.hpp"

namespace rdsim {

int export_command(const ExportOptions& o) {
  if (o.onnx_path.empty()) throw Error("--onnx: expected a file name, got an empty string");
  const ExportSummary s = export_onnx(o.model_path, o.onnx_path);
  std::printf("wrote %s (%lld bytes): %s on %s, input \"observation\" [batch, ...] float32, output \"action\"; %s\n",
              o.onnx_path.c_str(), s.bytes, s.algorithm.c_str(), s.env.c_str(), s.spec.c_str());
  std::printf("checked: its actions are rdsim's on %d observations (largest difference %.3g)\n", s.checked,
              s.max_difference);
  return 0;
}

Command export_command_entry() {
  return {"export", "Write a saved policy (model.bin) as an ONNX model: the deterministic action for a batch of observations",
          [](CLI::App& cmd) -> std::function<int()> {
            auto o = std::make_shared<ExportOptions>();
            cmd.add_option("model", o->model_path, "Model file written by `rdsim train` (model.bin, best_model.bin or checkpoint.bin)")
                ->required();
            cmd.add_option("--onnx", o->onnx_path, "The ONNX file to write")->required();
            return [o] { return export_command(*o); };
          }};
}

}  // namespace rdsim
