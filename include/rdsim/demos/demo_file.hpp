#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "rdsim/core/env.hpp"
#include "rdsim/demos/demonstration.hpp"

// Demonstration files (*.demo): one env, any number of episodes, appended one at a time.
//
// Layout, format version 1 (little-endian; FNV-1a 64 checksums, core/checksum.hpp):
//   offset  0  magic "RDSIMDEM" (8 bytes)
//           8  u32 format version (1)
//          12  u32 reserved, 0
//          16  u64 committed length: the file's bytes that hold complete episodes (header included)
//          24  u64 committed episodes
//          32  u64 checksum of bytes 0..31                                    (the commit record)
//          40  u64 n, n bytes of header JSON, u64 checksum of the u64 n and the JSON
//              header: {"format": "rdsim demonstrations", "rdsim_version": "...",
//                       "env": <resolved env config>, "spec": <env name, spaces, step limit>}
//   then one record per episode:
//              u32 record magic "EPIS", u64 body length L, L bytes of body,
//              u64 checksum of the magic, L and the body
//              body: u64 m, m bytes of episode JSON {"source": "scripted" | "human",
//                    "seed": <reset seed> | null, "env": <resolved env config>, "steps": n,
//                    "terminated": bool, "truncated": bool, "return": sum of rewards, "success": bool},
//                    observations (n + 1 of them: Float32 as f32, UInt8 as bytes, each the spec's
//                    observation size), actions (n: Discrete as i32, Box as dim f32), rewards (n f32),
//                    distances (n f32: StepInfo::distance), flags (n u8: 1 success, 2 collision,
//                    4 out of bounds).
//
// Writing (DemoWriter): a record is written after the last committed byte and flushed to disk
// (fsync), and only then is the commit record rewritten (24 bytes in the first disk sector) and
// flushed. A crash therefore loses at most the episode being written: its bytes lie beyond the
// committed length, and readers ignore them (DemoFile::interrupted_bytes). A file shorter than its
// committed length was cut short (copy, disk full): that is an error, as is any checksum mismatch.
namespace rdsim {

inline constexpr std::uint32_t demo_format_version = 1;
// The largest demonstration file rdsim reads (it is read whole: training keeps every episode).
inline constexpr std::uint64_t max_demo_file_bytes = 64ull << 30;

struct DemoFile {
  std::string path;                    // where it was read from (messages)
  std::uint32_t version = demo_format_version;
  std::string rdsim_version;           // of the rdsim that created the file
  nlohmann::json env_config;           // the resolved "env" object of the env it holds
  Spec spec;                           // env name, observation type and shape, action space, step limit
  std::vector<DemoEpisode> episodes;
  std::uint64_t interrupted_bytes = 0; // bytes after the committed ones (a write cut by a crash), ignored
};

// The file's bytes for `header` and no episode yet.
std::string encode_demo_file(const nlohmann::json& env_config, const Spec& spec);
// One episode record (validated first: validate_episode).
std::string encode_demo_episode(const DemoEpisode& episode, const Spec& spec, const std::string& where);

// Reads and checks everything: magic, version, checksums, lengths, that every episode fits the
// header's spaces and is a well-formed episode (validate_episode). One rdsim::Error naming
// `source` otherwise ("file is truncated", "file is damaged (...)", ...).
DemoFile decode_demo_file(std::string_view bytes, const std::string& source);
// The same for a file: only a regular file of at most max_demo_file_bytes, whose first 40 bytes
// (magic, version, commit record) are checked before the rest is read.
DemoFile read_demo_file(const std::string& path);

// The commit record of a file of `file_size` bytes that starts with `bytes` (at least its first
// 40 bytes), checked: magic, version, checksum, a committed length within the file. rdsim::Error
// naming `source` otherwise.
struct CommitRecord {
  std::uint32_t version = 0;
  std::uint64_t committed = 0;  // bytes that hold complete episodes, header included
  std::uint64_t episodes = 0;
};
CommitRecord read_commit_record(std::string_view bytes, std::uint64_t file_size, const std::string& source);

// rdsim::Error naming `where` when `episode` is not a well-formed episode of an env of `spec`:
// array lengths, observation sizes and types, actions outside the action space, non-finite values,
// an episode end before its last step.
void validate_episode(const DemoEpisode& episode, const Spec& spec, const std::string& where);

// The spec as the header stores it, and back (rdsim::Error naming `where` on a bad object).
nlohmann::json spec_to_json(const Spec& spec);
Spec spec_from_json(const nlohmann::json& json, const std::string& where);

// "Discrete(6)", "Box(3)"; "Float32[15]", "UInt8[64x64x3]".
std::string describe_action_space(const ActionSpace& space);
std::string describe_observation_space(const ObservationSpace& space);

}  // namespace rdsim
