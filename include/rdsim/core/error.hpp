#pragma once
#include <stdexcept>
#include <string>

namespace rdsim {

// Bad input from outside the program: a config, a URDF, a model file, a network message.
// what() is the complete message a user sees, so it names the file/field and what was expected.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

}  // namespace rdsim
