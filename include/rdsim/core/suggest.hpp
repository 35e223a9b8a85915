#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

// "Did you mean": the valid name closest to a mistyped one (config keys, env names, commands).
namespace rdsim {

// Levenshtein distance: the fewest single-character insertions, deletions and substitutions
// that turn `a` into `b`.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate `word` most likely meant, or "" when none is close enough to be a typo: the first
// candidate that `word` begins ("bench" -> "bench-fps"), else the fewest edits away (case ignored),
// when that is at most 2 edits or a third of the word's length, whichever is more.
std::string closest_name(std::string_view word, const std::vector<std::string>& candidates);

// ` (did you mean "NAME"?)` for closest_name, or "" when nothing is close.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace rdsim
