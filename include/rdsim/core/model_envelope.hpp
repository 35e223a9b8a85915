#pragma once
#include <cstdint>
#include <string>
#include <string_view>

// The bytes of a model.bin / checkpoint.bin around its parts, read by the training library (which
// gives the config and weights their meaning, training/model_file.hpp) and by the policy library
// (which needs only the policy part, policy/policy.hpp). Layout (little-endian):
//   magic "RDSIMMDL" (8 bytes) | u32 format version | u32 kind (0 model, 1 checkpoint)
//   | u64 n + n bytes: the resolved training config (JSON text)
//   | u64 n + n bytes: the env spec the weights were trained on (version >= 3)
//   | u64 n + n bytes: payload (the algorithm's weights; for checkpoints followed by trainer state)
//   | u64 n + n bytes: the policy alone (policy/policy_file.hpp; version >= 4; empty for an
//     algorithm without one, e.g. random)
//   | u64 FNV-1a 64 checksum of every byte before it
// Files are written atomically, so a reader sees the old file or the new one. The checksum catches
// accidental damage; each part is validated by its reader too, so an edited file with a
// recomputed checksum is still a clear error.
namespace rdsim {

// 4: the policy is recorded on its own (what a controller without rdsim's training code reads).
// 3: the env spec is recorded beside the config.
// 2: the embedded config records the env's real task numbers (published env defaults).
// 1: it recorded 0 for "the env's default" (training/model_file.hpp upgrades it).
inline constexpr std::uint32_t model_format_version = 4;

// Model files larger than this are refused before reading (64 GiB: far beyond any network or
// replay buffer the memory limit lets a run hold).
inline constexpr std::uint64_t max_model_file_bytes = 64ull << 30;

struct ModelEnvelope {
  std::uint32_t version = model_format_version;  // as read; encoding always writes today's
  std::uint32_t kind = 0;                        // 0 model, 1 checkpoint
  std::string config;                            // JSON text
  std::string spec;                              // empty in version 1-2 files
  std::string payload;
  std::string policy;                            // empty in version 1-3 files
};

std::string encode_model_envelope(const ModelEnvelope& envelope);
// rdsim::Error naming `source` for a foreign file (magic), an unknown version, a truncated file,
// a checksum mismatch (damaged file) or an unknown kind.
ModelEnvelope decode_model_envelope(std::string_view bytes, const std::string& source);
// Reads at most max_model_file_bytes from a regular file (a large foreign file is refused after
// its first 8 bytes).
ModelEnvelope read_model_envelope(const std::string& path);

}  // namespace rdsim
