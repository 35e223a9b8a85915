#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "rdsim/core/env.hpp"
#include "rdsim/core/model_envelope.hpp"

// model.bin / checkpoint.bin as the training library reads them: the envelope (layout and checks in
// core/model_envelope.hpp) with its config parsed. The contents are validated after the checksum
// too (config by the config rules, spec against the env the config builds, weights finite and of
// the right shapes, counters in range), so an edited file with a recomputed checksum is still a
// clear error.
namespace rdsim {

enum class ModelKind : std::uint32_t { Model = 0, Checkpoint = 1 };

struct ModelFile {
  ModelKind kind = ModelKind::Model;
  nlohmann::json config;  // to_json(TrainConfig)
  std::string spec;       // describe_spec() of the envs it was trained on; empty in version 1-2 files
  std::string payload;
  std::string policy;     // the policy alone (policy/policy_file.hpp); empty before version 4 or without one
};

// "jaka_button: observation float32 {6}, actions discrete 6": what the weights' shapes depend on.
std::string describe_spec(const Spec& spec);
// rdsim::Error naming `source` when the file records a spec and `spec` (of the env its config
// builds) differs: an edited config, e.g. another env's name, would otherwise load weights meant
// for something else.
void check_model_spec(const ModelFile& file, const Spec& spec, const std::string& source);

std::string encode_model_file(const ModelFile& file);
// rdsim::Error naming `source` for what decode_model_envelope refuses or an embedded config that
// is not bounded, valid JSON (core/json_text.hpp). A version 1 file's config is upgraded to
// today's form (upgrade_v1_config).
ModelFile decode_model_file(std::string_view bytes, const std::string& source);

void write_model_file(const std::string& path, const ModelFile& file);
// Reads at most max_model_file_bytes from a regular file.
ModelFile read_model_file(const std::string& path);

}  // namespace rdsim
