#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

// model.bin / checkpoint.bin. Layout (little-endian):
//   magic "RDSIMMDL" (8 bytes) | u32 format version | u32 kind (0 model, 1 checkpoint)
//   | u64 n + n bytes: the resolved training config (JSON text)
//   | u64 n + n bytes: payload (Algorithm::save output; for checkpoints preceded by trainer state)
//   | u64 FNV-1a 64 checksum of every byte before it
// Files are written with write_file_atomic, so a reader sees the old file or the new one.
namespace rdsim {

enum class ModelKind : std::uint32_t { Model = 0, Checkpoint = 1 };

struct ModelFile {
  ModelKind kind = ModelKind::Model;
  nlohmann::json config;  // to_json(TrainConfig)
  std::string payload;
};

// 2: the embedded config records the env's real task numbers (published env defaults).
// 1: it recorded 0 for "the env's default"; decode_model_file still reads it (upgrade_v1_config).
inline constexpr std::uint32_t model_format_version = 2;

std::string encode_model_file(const ModelFile& file);
// rdsim::Error naming `source` for a foreign file (magic), an unknown version, a truncated file
// or a checksum mismatch (damaged file). A version 1 file's config is upgraded to today's form.
ModelFile decode_model_file(std::string_view bytes, const std::string& source);

void write_model_file(const std::string& path, const ModelFile& file);
ModelFile read_model_file(const std::string& path);

}  // namespace rdsim
