#pragma once
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rdsim {

// Bad input from outside the program: a config, a URDF, a model file, a network message.
// what() is the complete message a user sees, so it names the file/field and what was expected.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// `text` made safe to print on one line of a terminal: control characters and bytes outside
// printable ASCII/UTF-8 become \xNN escapes (a newline inside a value can never split an error
// message), and anything past `max_chars` is cut with "...".
std::string one_line(std::string_view text, std::size_t max_chars = 400);

}  // namespace rdsim
