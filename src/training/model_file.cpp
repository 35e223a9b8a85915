#include "rdsim/training/model_file.hpp"

#include "rdsim/training/train_config.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/json_text.hpp"

namespace rdsim {

std::string encode_model_file(const ModelFile& file) {
  return encode_model_envelope(ModelEnvelope{.kind = static_cast<std::uint32_t>(file.kind),
                                             .config = file.config.dump(),
                                             .spec = file.spec,
                                             .payload = file.payload,
                                             .policy = file.policy});
}

namespace {

ModelFile model_file(ModelEnvelope&& e, const std::string& source) {
  ModelFile file;
  file.kind = static_cast<ModelKind>(e.kind);
  file.config = parse_json(e.config, source + " (embedded config)");
  if (!file.config.is_object()) throw Error(source + ": file is damaged (its embedded config is not a JSON object)");
  if (e.version == 1) upgrade_v1_config(file.config);
  file.spec = std::move(e.spec);
  file.payload = std::move(e.payload);
  file.policy = std::move(e.policy);
  return file;
}

}  // namespace

ModelFile decode_model_file(std::string_view bytes, const std::string& source) {
  return model_file(decode_model_envelope(bytes, source), source);
}

std::string describe_spec(const Spec& spec) {
  std::string s = spec.env_name + ": observation " + (spec.observation.type == ObsType::UInt8 ? "uint8 {" : "float32 {");
  for (std::size_t i = 0; i < spec.observation.shape.size(); ++i)
    s += (i ? ", " : "") + std::to_string(spec.observation.shape[i]);
  s += "}, actions ";
  s += spec.action.discrete ? "discrete " + std::to_string(spec.action.n) : "box " + std::to_string(spec.action.dim());
  return s;
}

void check_model_spec(const ModelFile& file, const Spec& spec, const std::string& source) {
  if (file.spec.empty() || file.spec == describe_spec(spec)) return;
  throw Error(source + ": file is damaged or edited: its weights were trained on \"" + one_line(file.spec, 120) +
              "\" but its config builds \"" + describe_spec(spec) + "\"");
}

void write_model_file(const std::string& path, const ModelFile& file) { write_file_atomic(path, encode_model_file(file)); }

ModelFile read_model_file(const std::string& path) { return model_file(read_model_envelope(path), path); }

}  // namespace rdsim
