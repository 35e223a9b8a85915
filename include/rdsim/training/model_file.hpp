#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "rdsim/core/env.hpp"

// model.bin / checkpoint.bin. Layout (little-endian):
//   magic "RDSIMMDL" (8 bytes) | u32 format version | u32 kind (0 model, 1 checkpoint)
//   | u64 n + n bytes: the resolved training config (JSON text)
//   | u64 n + n bytes: the env spec the weights were trained on (describe_spec; version >= 3)
//   | u64 n + n bytes: payload (Algorithm::save output; for checkpoints followed by trainer state)
//   | u64 FNV-1a 64 checksum of every byte before it
// Files are written with write_file_atomic, so a reader sees the old file or the new one. The
// checksum catches accidental damage; the contents are validated after it too (config by the
// config rules, spec against the env the config builds, weights finite and of the right shapes,
// counters in range), so an edited file with a recomputed checksum is still a clear error.
namespace rdsim {

enum class ModelKind : std::uint32_t { Model = 0, Checkpoint = 1 };

struct ModelFile {
  ModelKind kind = ModelKind::Model;
  nlohmann::json config;  // to_json(TrainConfig)
  std::string spec;       // describe_spec() of the envs it was trained on; empty in version 1-2 files
  std::string payload;
};

// Model files larger than this are refused before reading (64 GiB: far beyond any network or
// replay buffer the memory limit lets a run hold).
inline constexpr std::uint64_t max_model_file_bytes = 64ull << 30;

// "jaka_button: observation float32 {6}, actions discrete 6": what the weights' shapes depend on.
std::string describe_spec(const Spec& spec);
// rdsim::Error naming `source` when the file records a spec and `spec` (of the env its config
// builds) differs: an edited config, e.g. another env's name, would otherwise load weights meant
// for something else.
void check_model_spec(const ModelFile& file, const Spec& spec, const std::string& source);

// 3: the env spec is recorded beside the config.
// 2: the embedded config records the env's real task numbers (published env defaults).
// 1: it recorded 0 for "the env's default"; decode_model_file still reads it (upgrade_v1_config).
inline constexpr std::uint32_t model_format_version = 3;

std::string encode_model_file(const ModelFile& file);
// rdsim::Error naming `source` for a foreign file (magic), an unknown version, a truncated file,
// a checksum mismatch (damaged file) or an embedded config that is not bounded, valid JSON
// (core/json_text.hpp). A version 1 file's config is upgraded to today's form.
ModelFile decode_model_file(std::string_view bytes, const std::string& source);

void write_model_file(const std::string& path, const ModelFile& file);
// Reads at most max_model_file_bytes from a regular file.
ModelFile read_model_file(const std::string& path);

}  // namespace rdsim
