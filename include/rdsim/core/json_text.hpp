#pragma once
#include <cstddef>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

// JSON text from outside the program (config files, the config embedded in a model file, network
// messages) turned into nlohmann::json with every limit checked BEFORE parsing, so that no input
// can exhaust the stack or memory, and every problem is one rdsim::Error naming `where`:
//  - at most `max_bytes` of text (configs: max_config_bytes);
//  - arrays and objects nested at most max_json_depth deep (a 60,000-deep value would overflow
//    the stack of any recursive consumer: dump, destructor, comparison);
//  - a key repeated in one object is an error (nlohmann would keep the last one silently);
//  - a number beyond double range (1e400) is an error, not an exception from inside nlohmann.
// JSON has no NaN or infinity literals, so a parsed value never holds one.
namespace rdsim {

inline constexpr std::uint64_t max_config_bytes = 16ull * 1024 * 1024;  // 16 MiB
inline constexpr int max_json_depth = 64;

nlohmann::json parse_json(std::string_view text, const std::string& where,
                          std::uint64_t max_bytes = max_config_bytes);

// A config file read with read_file's bounds (max_config_bytes) and parsed by parse_json.
nlohmann::json read_json_file(const std::string& path);

// Compact JSON text of any value: bytes that are not UTF-8 (a string cut inside a character, a
// name in another encoding, bytes a client sent) are written as U+FFFD instead of throwing, so a
// reply or an error message about bad input can always be written.
std::string dump_json(const nlohmann::json& value);

// A short, single-line rendering of a value for error messages: compact JSON cut to about
// `max_chars` characters ("..." marks the cut). Iterative and bounded: it never walks more of
// the value than it prints, whatever the value's size or depth.
std::string json_excerpt(const nlohmann::json& value, std::size_t max_chars = 60);

}  // namespace rdsim
